#include "encoder/shape/depth_map.h"

#include <algorithm>
#include <cmath>

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
  const int w = map.width, h = map.height;
  map.depth.assign(size_t(w) * h, std::numeric_limits<float>::infinity());
  std::vector<Eigen::Vector2d> px(positions.size());
  std::vector<float> inv_z(positions.size(), 0);
  for (size_t v = 0; v < positions.size(); ++v) {
    double z = 0;
    if (ProjectPoint(camera, positions[v].cast<double>(), &px[v], &z)) inv_z[v] = float(1 / z);
  }
  for (const auto& tri : triangles) {
    if (inv_z[tri[0]] <= 0 || inv_z[tri[1]] <= 0 || inv_z[tri[2]] <= 0) continue;
    const Eigen::Vector2d a = px[tri[0]], b = px[tri[1]], c = px[tri[2]];
    const double area = (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
    if (std::abs(area) < 1e-12) continue;
    // Bounds clamped in double first: a vertex near the camera plane projects
    // far outside the image, beyond what an int holds.
    const auto lo = [](double v, int limit) {
      return int(std::clamp(std::ceil(v), 0.0, double(limit)));
    };
    const auto hi = [](double v, int limit) {
      return int(std::clamp(std::floor(v), -1.0, double(limit - 1)));
    };
    const int x0 = lo(std::min({a.x(), b.x(), c.x()}), w);
    const int x1 = hi(std::max({a.x(), b.x(), c.x()}), w);
    const int y0 = lo(std::min({a.y(), b.y(), c.y()}), h);
    const int y1 = hi(std::max({a.y(), b.y(), c.y()}), h);
    const double inv = 1.0 / area;
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const double w0 = ((c.x() - b.x()) * (y - b.y()) - (c.y() - b.y()) * (x - b.x())) * inv;
        const double w1 = ((a.x() - c.x()) * (y - c.y()) - (a.y() - c.y()) * (x - c.x())) * inv;
        const double w2 = 1 - w0 - w1;
        if (w0 < 0 || w1 < 0 || w2 < 0) continue;
        const float z = float(1 / (w0 * inv_z[tri[0]] + w1 * inv_z[tri[1]] + w2 * inv_z[tri[2]]));
        float& d = map.depth[size_t(y) * w + x];
        d = std::min(d, z);
      }
    }
  }
  return map;
}

}  // namespace fvv
