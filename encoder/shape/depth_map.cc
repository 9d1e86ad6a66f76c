#include "encoder/shape/depth_map.h"

#include <algorithm>
#include <cmath>

#include "container/geometric_visibility.h"
#include "encoder/capture/calibration.h"

namespace fvv {

float DepthMap::At(const Eigen::Vector2d& pixel) const {
  const long x = std::lround(pixel.x()), y = std::lround(pixel.y());
  if (!(x >= 0 && y >= 0 && x < width && y < height)) return std::numeric_limits<float>::infinity();
  return depth[size_t(y) * width + x];
}

DepthMap RenderDepthMap(const std::vector<std::array<uint32_t, 3>>& triangles,
                        const std::vector<Eigen::Vector3f>& positions, const Camera& camera) {
  DepthMap map;
  map.width = int(camera.width);
  map.height = int(camera.height);
  std::vector<double> px(positions.size() * 2, 0.0);
  std::vector<float> inv_z(positions.size(), 0);
  for (size_t v = 0; v < positions.size(); ++v) {
    Eigen::Vector2d q;
    double z = 0;
    if (ProjectPoint(camera, positions[v].cast<double>(), &q, &z)) {
      inv_z[v] = float(1 / z);
      px[2 * v] = q.x();
      px[2 * v + 1] = q.y();
    }
  }
  map.depth = RasterizeDepth(triangles.empty() ? nullptr : triangles[0].data(), triangles.size(),
                             px.data(), inv_z.data(), map.width, map.height);
  return map;
}

}  // namespace fvv
