// Something other than the actor between a camera and him: a crew member,
// another performer, a prop. Resampling knows only the actor's posed body, so
// a camera whose view of his surface is blocked would sample what blocks it.
//
// The cameras' silhouettes hold everything in front of the background (given
// silhouettes, or background subtraction against plates); where a silhouette
// reaches further from the actor's posed model than the fit's error, it holds
// something else. A coarse voxel grid around the actor keeps each voxel that
// every camera seeing it finds inside its silhouette and at least one finds in
// such unexplained foreground: the visual hull of what else stands there. Its
// depth in each camera tells resampling where a surface point lies behind it.
// With the person network's masks (the actor's own, no one else's) the
// silhouettes hold nobody else, and nothing is found here.
#ifndef FVV_ENCODER_ENCODE_OCCLUDERS_H_
#define FVV_ENCODER_ENCODE_OCCLUDERS_H_

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "codec/base/parallel.h"
#include "container/cameras.h"
#include "encoder/io/image_io.h"

namespace fvv {

struct OccluderOptions {
  bool enabled = true;
  double voxel_size = 0.04;  // metres
  double reach = 1.5;        // metres searched around the actor's bounding box
  // Foreground within this distance (metres, in the image at the actor's
  // depth) of the posed model's outline is the actor's own: the fit's error.
  double explained_margin = 0.08;
  int max_side = 480;              // pixels: the cameras are worked at about this size
  uint64_t max_voxels = 8u << 20;  // a larger grid takes larger voxels
  // A camera whose unexplained foreground is over this share of what the
  // model covers (OccluderReport::unexplained_share) is suspect in that
  // frame: its samples are kept only where another camera seeing the point
  // saw its colour, within `suspect_difference` levels (mean over R, G, B;
  // encoder/encode/sample_agreement.h). 0: no camera is suspect.
  double suspect_share = 0.1;
  double suspect_difference = 40;
};

// One camera's depth of what else stands in its view, on its image reduced by
// `factor` (0: nothing was found).
struct OccluderDepth {
  int factor = 0;
  int width = 0, height = 0;
  std::vector<float> depth;  // camera z, +infinity where nothing else is

  // Whether something other than the actor stands in front of depth `z` at
  // the full-resolution pixel (x, y) by more than `clearance` metres (nearer,
  // it may be the actor's own outline that the posed model misses).
  bool Hides(int x, int y, double z, double clearance) const;
};

struct OccluderReport {
  uint64_t voxels = 0;  // voxels of the hull of what else stands there
  // Per camera: its silhouette's foreground that neither the actor's model
  // nor the hull of what else stands there explains, as a share of what the
  // model covers (at the reduced size). A camera whose mask takes in someone
  // the other cameras' masks do not hold (the person network's mask of the
  // actor, with another person close in front of that camera) shows here,
  // though no hull can be carved of him.
  std::vector<double> unexplained_share;
};

// `positions`: the actor's posed vertices (world space) of `triangles`. One
// silhouette per camera (grey, non-zero = foreground, the camera's size).
std::vector<OccluderDepth> FindOccluders(const std::vector<Camera>& cameras,
                                         const std::vector<Image>& silhouettes,
                                         const std::vector<std::array<uint32_t, 3>>& triangles,
                                         const std::vector<Eigen::Vector3f>& positions,
                                         const OccluderOptions& options, OccluderReport* report,
                                         const ParallelRunner& runner = SerialRunner);

}  // namespace fvv

#endif  // FVV_ENCODER_ENCODE_OCCLUDERS_H_
