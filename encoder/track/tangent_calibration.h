// Camera orientations refined from the actor's silhouettes alone, with no
// body model: the epipolar geometry of two cameras is right when the lines
// through the other camera's centre that touch one camera's silhouette map to
// the lines that touch the other's (they lie in the planes through both
// centres that touch the actor, and meet his surface at the same points), as
// camera-network calibration from dynamic silhouettes has it. The outline
// refinement (silhouette_calibration.h) lays a tracked body model on the
// masks, so a pose or a shape a centimetre off turns the cameras with it;
// here nothing but the masks and the cameras' centres enters. Every pair of
// cameras in every frame gives two tangents, each a pixel distance between a
// tangent point and the epipolar line of the other camera's; the rotations of
// all cameras are adjusted together (Levenberg-Marquardt, Huber-weighted, a
// weak prior towards the calibration). Roll, centres and intrinsics stay as
// calibrated: what tangents measure best is orientation, and a camera's centre
// fixes its epipoles.
#ifndef FVV_ENCODER_TRACK_TANGENT_CALIBRATION_H_
#define FVV_ENCODER_TRACK_TANGENT_CALIBRATION_H_

#include <cstdint>
#include <vector>

#include "codec/base/status.h"
#include "container/cameras.h"
#include "encoder/track/outline_hull.h"

namespace fvv {

struct TangentCalibrationOptions {
  double huber_px = 2.0;  // tangents further off than this count linearly
  // The prior: a turn that moves a camera's image by this many pixels costs
  // as much as one tangent a pixel off.
  double prior_px = 20;
  int iterations = 30;
  // Tangents from an epipole that sees the silhouette over a wider angle than
  // this are left out: near the silhouette a tangent's direction is ill-posed.
  double max_cone_deg = 120;
  // A camera that would turn further than this is refused: the calibration is
  // wrong in another way than a bumped camera.
  double max_turn_deg = 3.0;
  // Turn the cameras about their optical axes too. Off by default: the
  // tangents of an actor in the middle of the image say little of it (a
  // roll moves his outline by its distance from the image's centre times the
  // angle), and a bumped camera pans and tilts far more than it rolls.
  bool roll = false;
  // A combination of turns that moves the images by a pixel must move the
  // tangents by this much (mean square, pixels squared) to be turned along;
  // the others stay as calibrated. A ring of cameras around the actor, tilted
  // down together, sees his tangents move together: the tangents hardly tell
  // it from an actor standing higher, so masks a pixel off at the feet would
  // tilt every camera by several.
  double min_information = 0.005;
};

struct TangentCalibration {
  std::vector<Camera> cameras;  // refined
  // Per camera: the median distance (pixels) of its tangent points from the
  // epipolar lines of the other cameras' matching ones, before and after.
  std::vector<double> before_px, after_px;
  std::vector<double> turn_deg;    // per camera
  std::vector<uint32_t> tangents;  // per camera, the tangent points measured
  int held_directions = 0;         // combinations of turns left as calibrated (min_information)
  // The Huber cost per tangent point after (pixels squared below huber_px):
  // what two sets of outlines are compared by (tangent_sync.h).
  double mean_cost = 0;
  int iterations = 0;
};

// Per camera: the median distance described above; -1 for a camera with no
// tangent. `outlines[frame][camera]`, an empty hull where a camera has none.
std::vector<double> TangentDistances(const std::vector<Camera>& cameras,
                                     const std::vector<std::vector<OutlineHull>>& outlines,
                                     const TangentCalibrationOptions& options = {},
                                     std::vector<uint32_t>* tangents = nullptr);

// Needs 2 cameras or more and at least 20 tangents.
StatusOr<TangentCalibration> RefineCamerasFromTangents(
    const std::vector<Camera>& cameras, const std::vector<std::vector<OutlineHull>>& outlines,
    const TangentCalibrationOptions& options = {});

}  // namespace fvv

#endif  // FVV_ENCODER_TRACK_TANGENT_CALIBRATION_H_
