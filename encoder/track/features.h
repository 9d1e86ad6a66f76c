// Sparse feature points of a capture: named points (the
// generic body's joint centres, e.g. from a studio's annotation or a 2D
// keypoint detector) marked in camera images, in a JSON file:
//
//   {"features": [{"frame": 0, "camera": "cam00", "points": {"l_knee": [x, y], ...}},
//                 ...]}
//
// pixel coordinates as the calibration's (pixel centres at integers, lens
// distortion included). Each named point of a frame seen by two or more
// cameras is reconstructed in 3D by linear triangulation of the undistorted
// rays, refined by Gauss-Newton on the reprojection error.
#ifndef FVV_ENCODER_TRACK_FEATURES_H_
#define FVV_ENCODER_TRACK_FEATURES_H_

#include <Eigen/Core>
#include <map>
#include <string>
#include <vector>

#include "codec/base/status.h"
#include "container/cameras.h"

namespace fvv {

// Per frame: per point name, per camera index, its pixel.
struct FeatureSet {
  std::map<uint32_t, std::map<std::string, std::map<uint32_t, Eigen::Vector2d>>> frames;
};

// Point names the file may use: the generic body's joints.
bool IsFeatureName(const std::string& name);

// Parses features JSON against the capture's cameras; `what` names the file in
// errors (unknown cameras or names, coordinates outside the image, frames
// beyond `frame_count`).
StatusOr<FeatureSet> ParseFeatures(const std::string& text, const std::vector<Camera>& cameras,
                                   uint32_t frame_count, const std::string& what);
StatusOr<FeatureSet> LoadFeatures(const std::string& path, const std::vector<Camera>& cameras,
                                  uint32_t frame_count);
std::string FeaturesToJson(const FeatureSet& features, const std::vector<Camera>& cameras);

struct Feature3D {
  Eigen::Vector3d position{0, 0, 0};
  int views = 0;
  double rms_px = 0;  // reprojection error over its views
};

// The frame's points seen by at least two cameras, in 3D. A point whose
// reprojection error exceeds `max_rms_px` is made again from its views less
// one (a mislabelled view), the best that agrees; else it is left out.
std::map<std::string, Feature3D> TriangulateFeatures(
    const std::map<std::string, std::map<uint32_t, Eigen::Vector2d>>& points,
    const std::vector<Camera>& cameras, double max_rms_px = 4.0);

}  // namespace fvv

#endif  // FVV_ENCODER_TRACK_FEATURES_H_
