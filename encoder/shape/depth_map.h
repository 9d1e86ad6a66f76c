// A camera's depth map of a posed mesh, rasterised on the CPU: the nearest
// surface's camera z at every pixel centre (pixel centres at integer
// coordinates, as the calibration's), interpolated perspective-correctly. The
// visibility tests of multi-view resampling (the encoder) and of projective
// texturing (Renderer I) compare a surface point's depth against it, shadow-map
// style.
#ifndef FVV_ENCODER_SHAPE_DEPTH_MAP_H_
#define FVV_ENCODER_SHAPE_DEPTH_MAP_H_

#include <Eigen/Core>
#include <array>
#include <limits>
#include <vector>

#include "container/cameras.h"

namespace fvv {

struct DepthMap {
  int width = 0, height = 0;
  std::vector<float> depth;  // row-major; +infinity where no surface projects

  // The depth at the pixel nearest `pixel` (+infinity outside the image).
  float At(const Eigen::Vector2d& pixel) const;
};

// `positions` are the mesh's vertices in world space; triangles with a vertex
// at or behind the camera are skipped (they cannot occlude what it sees of an
// actor in front of it).
DepthMap RenderDepthMap(const std::vector<std::array<uint32_t, 3>>& triangles,
                        const std::vector<Eigen::Vector3f>& positions, const Camera& camera);

}  // namespace fvv

#endif  // FVV_ENCODER_SHAPE_DEPTH_MAP_H_
