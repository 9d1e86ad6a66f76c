// The texture atlas of a body model (built once per model): charts
// grown from a seed triangle within each body segment, adding neighbours while
// a triangle's normal stays within a limit of the chart's average normal;
// each chart projected orthographically onto the plane of its average normal
// (aligned with its principal axes) and packed into one square atlas with
// gutters, at one texel density for the whole body (texels proportional to
// surface area). Vertices on chart borders are duplicated, one per chart.
#ifndef FVV_ENCODER_ATLAS_ATLAS_H_
#define FVV_ENCODER_ATLAS_ATLAS_H_

#include <Eigen/Core>
#include <vector>

#include "codec/base/status.h"
#include "container/body_model.h"

namespace fvv {

struct AtlasOptions {
  uint32_t size = 512;                 // atlas side in texels, 16..4096
  double max_normal_deviation = 50.0;  // degrees from the chart's average normal
  uint32_t gutter = 2;                 // free texels around every chart
};

struct AtlasChart {
  int segment = 0;
  std::vector<uint32_t> triangles;               // into the atlas mesh
  Eigen::Vector3d normal;                        // projection direction (average normal)
  uint32_t x = 0, y = 0, width = 0, height = 0;  // texels, gutter included
};

struct Atlas {
  uint32_t size = 0;
  double texels_per_metre = 0;
  std::vector<AtlasChart> charts;
  Mesh mesh;  // the model's mesh with atlas UVs (border vertices duplicated)
  // Index of the source vertex each atlas vertex copies.
  std::vector<uint32_t> source_vertex;
};

StatusOr<Atlas> BuildAtlas(const Mesh& mesh, const AtlasOptions& options = AtlasOptions());

}  // namespace fvv

#endif  // FVV_ENCODER_ATLAS_ATLAS_H_
