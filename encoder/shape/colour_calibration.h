// The cameras' colour responses, from what they see of the actor. Cameras of
// one rig rarely agree on colour: each has its own exposure and white
// balance, so the same patch of skin reads brighter or bluer in one than in
// another. The texture then changes colour where the blend passes from one
// camera to the next, and a view rendered from some cameras does not look
// like the footage of another. A response is modelled as a gain per channel
// on the pixel values (exposure and white balance scale light, and the video
// curve's power law keeps a scale a scale). At every vertex of the posed
// model that two cameras see well (facing them, in front of their depth maps,
// inside their silhouettes with a margin, neither too dark nor clipped), the
// two colours' log ratio is one measure of the two responses' ratio; the
// median over all such points and frames, per pair of cameras and channel,
// is robust to the misfits near outlines and to specular spots, and the
// responses are the least-squares solution of all pairs' medians, their
// geometric mean 1 (the rig's common colour).
#ifndef FVV_ENCODER_SHAPE_COLOUR_CALIBRATION_H_
#define FVV_ENCODER_SHAPE_COLOUR_CALIBRATION_H_

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "codec/base/status.h"
#include "container/body_model.h"
#include "container/cameras.h"
#include "encoder/io/image_io.h"

namespace fvv {

struct ColourCalibrationOptions {
  double min_facing = 0.5;        // cosine between the normal and the way to the camera
  double depth_tolerance = 0.02;  // metres behind the depth map still seen
  // The silhouette must hold this share of the image's longer side away from
  // the point, up, down, left and right (the fit misses outlines by a few
  // pixels, and there the colour is the background's).
  double inner_margin = 0.005;
  int min_level = 12, max_level = 243;  // every channel within (noise, clipping)
  uint64_t min_pair_points = 200;       // a pair sharing fewer is not used
};

struct ColourPair {
  uint32_t a = 0, b = 0;          // cameras
  uint64_t points = 0;            // vertex-frames both saw
  std::array<double, 3> ratio{};  // median of a's colour over b's, per channel
};

struct ColourCalibrationResult {
  // Per camera: what its pixel values are multiplied by to read the rig's
  // common colour (1, 1, 1 where it shares no surface with another camera).
  std::vector<std::array<double, 3>> gains;
  std::vector<uint64_t> points;  // per camera: vertex-frames shared with another camera
  std::vector<bool> calibrated;  // per camera: shares enough with the others
  std::vector<ColourPair> pairs;
  // How far two cameras' colours at a shared point differ: the median of
  // |log ratio| (about a relative difference), per pair and channel, averaged
  // over channels and over pairs by their points; as read and with the gains.
  double difference_before = 0, difference_after = 0;
};

class ColourCalibration {
 public:
  explicit ColourCalibration(std::vector<Camera> cameras, ColourCalibrationOptions options = {});

  // One frame: the posed mesh (world space: vertex positions and normals)
  // and each camera's image (RGB8) and silhouette (grey, non-0 = actor; an
  // empty one: no silhouette test, the depth maps alone).
  Status AddFrame(const std::vector<std::array<uint32_t, 3>>& triangles,
                  const std::vector<Eigen::Vector3f>& positions,
                  const std::vector<Eigen::Vector3f>& normals, const std::vector<Image>& images,
                  const std::vector<Image>& silhouettes);

  uint32_t frames() const { return frames_; }

  // Fails where no two cameras share enough of the surface.
  StatusOr<ColourCalibrationResult> Solve() const;

 private:
  // Per pair (a < b) and channel: a histogram of log(a / b).
  static constexpr int kBins = 1600;
  static constexpr double kRange = 2.0;  // log ratios in [-kRange, kRange)
  size_t PairIndex(uint32_t a, uint32_t b) const;

  std::vector<Camera> cameras_;
  ColourCalibrationOptions o_;
  uint32_t frames_ = 0;
  std::vector<std::array<std::vector<uint32_t>, 3>> histograms_;
  std::vector<uint64_t> pair_points_;
};

}  // namespace fvv

#endif  // FVV_ENCODER_SHAPE_COLOUR_CALIBRATION_H_
