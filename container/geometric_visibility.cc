#include "container/geometric_visibility.h"

#include <limits>

namespace fvv {

std::vector<float> RasterizeDepth(const uint32_t* triangles, size_t triangle_count,
                                  const double* pixel, const float* inv_z, int width, int height) {
  const int w = width, h = height;
  std::vector<float> depth(size_t(w) * h, std::numeric_limits<float>::infinity());
  for (size_t t = 0; t < triangle_count; ++t) {
    const uint32_t* tri = triangles + 3 * t;
    if (inv_z[tri[0]] <= 0 || inv_z[tri[1]] <= 0 || inv_z[tri[2]] <= 0) continue;
    const double ax = pixel[2 * tri[0]], ay = pixel[2 * tri[0] + 1];
    const double bx = pixel[2 * tri[1]], by = pixel[2 * tri[1] + 1];
    const double cx = pixel[2 * tri[2]], cy = pixel[2 * tri[2] + 1];
    const double area = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
    if (!(std::abs(area) >= 1e-12)) continue;
    // Bounds clamped in double first: a vertex near the camera plane projects
    // far outside the image, beyond what an int holds.
    const auto lo = [](double v, int limit) {
      return int(std::clamp(std::ceil(v), 0.0, double(limit)));
    };
    const auto hi = [](double v, int limit) {
      return int(std::clamp(std::floor(v), -1.0, double(limit - 1)));
    };
    const int x0 = lo(std::min({ax, bx, cx}), w), x1 = hi(std::max({ax, bx, cx}), w);
    const int y0 = lo(std::min({ay, by, cy}), h), y1 = hi(std::max({ay, by, cy}), h);
    const double inv = 1.0 / area;
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const double w0 = ((cx - bx) * (y - by) - (cy - by) * (x - bx)) * inv;
        const double w1 = ((ax - cx) * (y - cy) - (ay - cy) * (x - cx)) * inv;
        const double w2 = 1 - w0 - w1;
        if (w0 < 0 || w1 < 0 || w2 < 0) continue;
        const float z = float(1 / (w0 * inv_z[tri[0]] + w1 * inv_z[tri[1]] + w2 * inv_z[tri[2]]));
        float& d = depth[size_t(y) * w + x];
        d = std::min(d, z);
      }
    }
  }
  return depth;
}

}  // namespace fvv
