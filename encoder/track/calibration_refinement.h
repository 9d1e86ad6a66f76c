// Camera poses refined from the actor's keypoints: a studio's calibration is
// measured once, with a wand or a board, and cameras get bumped, mounts sag
// and a calibration volume may not be the actor's; a few millimetres or a
// tenth of a degree are tens of pixels at the far side of a 1920-pixel image.
// The body joints every camera sees over a span of frames are points shared
// by the cameras: the camera orientations and centres, and the points, are
// adjusted together (bundle adjustment, Levenberg-Marquardt with the points
// eliminated, Huber-weighted pixel errors) to make the cameras' sightings
// meet. Intrinsics and distortion stay as calibrated. A weak prior towards the
// calibration fixes what sightings cannot (where the world's origin, axes and
// metre are), so the world frame stays the calibration's.
#ifndef FVV_ENCODER_TRACK_CALIBRATION_REFINEMENT_H_
#define FVV_ENCODER_TRACK_CALIBRATION_REFINEMENT_H_

#include <cstdint>
#include <vector>

#include "codec/base/status.h"
#include "container/cameras.h"
#include "encoder/track/joint_sighting.h"

namespace fvv {

struct CalibrationRefinementOptions {
  double min_confidence = 0.5;  // sightings below it are not used
  // Views more than this far from the rest are left out of a point's first
  // triangulation (TriangulateFeatures' tolerance).
  double tolerance_px = 20;
  int iterations = 50;
  // The prior: how far the calibration is believed to be off, one standard
  // deviation. The sightings outweigh it wherever they say anything.
  double prior_rotation_deg = 0.5, prior_centre_m = 0.01;
};

struct CalibrationRefinement {
  std::vector<Camera> cameras;  // refined; names, sizes and intrinsics as given
  // Per camera: the median distance (pixels) of its sightings from the
  // points made by all cameras, before and after.
  std::vector<double> before_px, after_px;
  // Per camera: how far it turned (degrees) and moved (metres).
  std::vector<double> rotation_deg, centre_m;
  std::vector<uint32_t> sightings;  // per camera, used
  uint32_t points = 0;              // joints of frames seen by two cameras or more
  int iterations = 0;
};

// `sightings[frame][camera]`. Needs two cameras or more and at least 20
// points; a camera that saw none keeps its calibration.
StatusOr<CalibrationRefinement> RefineCameraPoses(
    const std::vector<Camera>& cameras,
    const std::vector<std::vector<std::vector<JointSighting>>>& sightings,
    const CalibrationRefinementOptions& options = {});

}  // namespace fvv

#endif  // FVV_ENCODER_TRACK_CALIBRATION_REFINEMENT_H_
