// A real capture's cameras as a synthetic studio (`fvv synth --rig`): the
// same positions, orientations, focal lengths and image sizes, calibrated
// exactly, so a bench can tell what a rig of that layout allows from what its
// calibration and footage cost. Lens distortion is left out (the synthetic
// images are pinhole). The rig is moved on the floor so that the actor's
// place is the synthetic studio's centre: where the real take's poses put
// the actor on average (`poses`, a poses.json of a take that rig filmed, in
// the capture's world), else the point nearest every camera's optical axis.
#ifndef FVV_TOOLS_SYNTH_RIG_H_
#define FVV_TOOLS_SYNTH_RIG_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "codec/base/status.h"
#include "container/cameras.h"
#include "encoder/body/generic_body.h"

namespace fvv {

struct Rig {
  std::vector<Camera> cameras;
  Eigen::Vector3d moved_by = Eigen::Vector3d::Zero();  // added to the capture's world (y = 0)
  // With poses: frames 0 .. frames - 1 of them, moved with the rig, and the
  // proportions they were fitted with.
  std::vector<std::vector<double>> poses;
  BodyShape shape;
};

// `capture`: a capture directory or capture.json; `poses`: a poses.json, or
// empty. `frames`: how many frames of the poses are wanted.
StatusOr<Rig> LoadRig(const std::string& capture, const std::string& poses, uint32_t frames);

// The point nearest every camera's optical axis (least squares), on the
// floor (y = 0); the cameras' mean centre where the axes are parallel.
Eigen::Vector3d NearestPointToAxes(const std::vector<Camera>& cameras);

}  // namespace fvv

#endif  // FVV_TOOLS_SYNTH_RIG_H_
