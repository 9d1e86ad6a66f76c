// A loose garment for the built-in synthetic actor: loose shorts whose cloth
// stands off the body by more as the legs swing apart, a moment late (a
// simple secondary-motion rule: the flare follows the knees' spread through a
// first-order lag). The surface then moves apart from the skeleton, frame by
// frame, which is what the surface of every frame (fvv encode --surface) must
// follow; the true surface of each frame goes into the truth.
#ifndef FVV_TOOLS_SYNTH_GARMENT_H_
#define FVV_TOOLS_SYNTH_GARMENT_H_

#include <Eigen/Core>
#include <vector>

#include "container/body_model.h"

namespace fvv {

// Per frame of `poses` (generic-body DOFs), the bind-pose positions of the
// model with the garment: pelvis and thigh vertices moved along their normals
// by up to about `amplitude` metres (the thighs' lower third fades to the
// knee). Welded copies move together: the mesh stays closed.
std::vector<std::vector<Eigen::Vector3f>> GarmentPositions(
    const BodyModel& model, const std::vector<std::vector<double>>& poses, double amplitude);

}  // namespace fvv

#endif  // FVV_TOOLS_SYNTH_GARMENT_H_
