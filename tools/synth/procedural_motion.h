// A built-in motion for the generic body model when no BVH file is given (or
// the CMU files are not installed): a natural walk along a circle with arm
// swing, torso counter-rotation and head turns. Deterministic, any length.
#ifndef FVV_TOOLS_SYNTH_PROCEDURAL_MOTION_H_
#define FVV_TOOLS_SYNTH_PROCEDURAL_MOTION_H_

#include <vector>

#include "container/body_model.h"

namespace fvv {

// `frames` poses at `fps` for the generic body (Skeleton::Dofs() order).
std::vector<std::vector<double>> ProceduralWalk(const Skeleton& skeleton, uint32_t frames,
                                                double fps);

}  // namespace fvv

#endif  // FVV_TOOLS_SYNTH_PROCEDURAL_MOTION_H_
