// The visual hull of an actor from calibrated silhouettes (volumetric shape from
// silhouettes): voxels are carved away wherever they project outside any
// camera's silhouette. Coarse to fine: a coarse grid over the whole studio
// finds the actor, a fine one (1 cm by default) carves it. A voxel is kept for
// a camera when the silhouette comes within its projected radius (plus a
// margin for calibration and edge error), so the hull is conservative: it
// contains the actor. Cameras that do not see a voxel do not carve it.
#ifndef FVV_ENCODER_SHAPE_VISUAL_HULL_H_
#define FVV_ENCODER_SHAPE_VISUAL_HULL_H_

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "codec/base/parallel.h"
#include "codec/base/status.h"
#include "container/cameras.h"
#include "encoder/io/image_io.h"

namespace fvv {

struct VisualHullOptions {
  double voxel_size = 0.01;         // metres, the fine grid
  double coarse_size = 0.08;        // metres, the search over the studio
  double margin_px = 1.0;           // silhouettes count as this many pixels larger
  int min_views = 2;                // cameras that must see a voxel for it to be kept
  uint64_t max_voxels = 64u << 20;  // per grid: a larger one is refused, not allocated
};

struct VisualHull {
  Eigen::Vector3d origin{0, 0, 0};  // the corner of voxel (0, 0, 0)
  double voxel_size = 0;
  std::array<int, 3> dims{0, 0, 0};
  std::vector<uint8_t> occupied;  // x fastest, then y, then z

  size_t Index(int x, int y, int z) const { return (size_t(z) * dims[1] + y) * dims[0] + x; }
  bool At(int x, int y, int z) const;  // false outside the grid
  Eigen::Vector3d Centre(int x, int y, int z) const;
  // Whether `p` lies in an occupied voxel.
  bool Contains(const Eigen::Vector3d& p) const;
  size_t OccupiedCount() const;
  double Volume() const;  // cubic metres
  // Centres of the occupied voxels with an empty (or outside) face neighbour.
  std::vector<Eigen::Vector3d> SurfaceVoxels() const;
  // The hull's boundary as a closed triangle mesh: every face between an
  // occupied voxel and an empty one (or the grid's outside), two triangles
  // each, wound outwards, voxel corners shared.
  void SurfaceMesh(std::vector<Eigen::Vector3f>* positions,
                   std::vector<std::array<uint32_t, 3>>* triangles) const;
};

// One silhouette (grey, non-zero = actor) per camera, each the camera's size.
StatusOr<VisualHull> CarveVisualHull(const std::vector<Camera>& cameras,
                                     const std::vector<Image>& silhouettes,
                                     const VisualHullOptions& options = {},
                                     const ParallelRunner& runner = SerialRunner);

// Points as an ASCII PLY point cloud (temporary file, then rename).
Status WritePointCloudPly(const std::string& path, const std::vector<Eigen::Vector3d>& points);

}  // namespace fvv

#endif  // FVV_ENCODER_SHAPE_VISUAL_HULL_H_
