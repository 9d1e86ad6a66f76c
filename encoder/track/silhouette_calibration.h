// Camera orientations refined from the actor's outline. A camera turned a
// fraction of a degree since its calibration sees the tracked body beside the
// actor by the same image shift in every frame, whatever the pose
// (silhouette_shift.h); the body's joints, which the keypoint refinement
// (calibration_refinement.h) matches, sit where the network places them, a
// few centimetres off the body's centre in ways that depend on the view, so
// refining on them turns cameras by what the keypoints leave free. Here the
// rig is tracked over a span of frames with every camera, each camera is
// turned by the one shift that lays the fitted silhouettes on its masks
// (about its own x and y axes: no roll, no move, nothing the outlines do not
// ask for), and the rig is tracked again, until the shifts are below a pixel
// or the rounds run out. Intrinsics, centres and roll stay as calibrated.
#ifndef FVV_ENCODER_TRACK_SILHOUETTE_CALIBRATION_H_
#define FVV_ENCODER_TRACK_SILHOUETTE_CALIBRATION_H_

#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "codec/base/status.h"
#include "container/cameras.h"
#include "encoder/capture/capture.h"
#include "encoder/track/track_capture.h"

namespace fvv {

struct SilhouetteCalibrationOptions {
  uint32_t first = 0, last = 59;  // the span tracked each round
  int rounds = 3;
  // A round whose largest shift is below this is the last: the shift search is
  // good to about 2 pixels (silhouette_shift.h).
  double stop_px = 2.0;
  // A camera that would turn further than this in all is refused: the
  // calibration is wrong in another way than a bumped camera.
  double max_turn_deg = 3.0;
  TrackCaptureOptions track;  // silhouettes, person models, threads (frames set here)
  std::function<void(const std::string&)> progress;
};

struct SilhouetteCalibrationRound {
  std::vector<Eigen::Vector2d> shift_px;  // per camera, the shift found (and turned by)
  std::vector<double> iou, shifted_iou;   // per camera, the fit's mean IoU and at the shift
  double mean_iou = 0;                    // the fit's, over all cameras
};

struct SilhouetteCalibration {
  std::vector<Camera> cameras;  // refined
  std::vector<SilhouetteCalibrationRound> rounds;
  std::vector<double> turn_deg;  // per camera, how far it turned in all
};

// The camera turned about its own x and y axes so that what it sees at the
// principal point moves by `pixels` in the image.
Camera TurnedByImageShift(const Camera& camera, const Eigen::Vector2d& pixels);

// The angle (degrees) between two cameras' orientations.
double TurnBetween(const Camera& a, const Camera& b);

StatusOr<SilhouetteCalibration> RefineCamerasFromSilhouettes(
    const Capture& capture, const SilhouetteCalibrationOptions& options);

}  // namespace fvv

#endif  // FVV_ENCODER_TRACK_SILHOUETTE_CALIBRATION_H_
