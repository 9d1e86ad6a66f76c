#include "conformance/sample/sample_volume.h"

#include <algorithm>
#include <cmath>

namespace fvv {
namespace {

// Integer hash -> [0, 1): deterministic value noise on every platform.
double Hash(int x, int y) {
  uint32_t h = static_cast<uint32_t>(x) * 374761393u + static_cast<uint32_t>(y) * 668265263u;
  h = (h ^ (h >> 13)) * 1274126177u;
  return ((h ^ (h >> 16)) & 0xFFFFFF) / 16777216.0;
}

double ValueNoise(double x, double y) {
  const int xi = static_cast<int>(std::floor(x)), yi = static_cast<int>(std::floor(y));
  const double fx = x - xi, fy = y - yi;
  const double sx = fx * fx * (3 - 2 * fx), sy = fy * fy * (3 - 2 * fy);
  const double a = Hash(xi, yi), b = Hash(xi + 1, yi), c = Hash(xi, yi + 1),
               d = Hash(xi + 1, yi + 1);
  return (a + (b - a) * sx) * (1 - sy) + (c + (d - c) * sx) * sy;
}

// The scene in world units (about 0..1 across a view).
void Scene(double u, double v, double* rgb) {
  double n = 0, amp = 0.5, f = 6;
  for (int o = 0; o < 5; ++o, amp *= 0.5, f *= 2) n += amp * ValueNoise(u * f, v * f);
  const double stripes = 0.5 + 0.5 * std::sin(40 * u + 8 * std::sin(5 * v));
  const bool check =
      (static_cast<int>(std::floor(u * 12)) + static_cast<int>(std::floor(v * 12))) & 1;
  const double dx = u - 0.55, dy = v - 0.45;
  const double disc = std::exp(-(dx * dx + dy * dy) * 40);
  rgb[0] = 0.25 + 0.45 * n + 0.2 * disc + (v > 0.7 ? 0.15 * stripes : 0);
  rgb[1] = 0.2 + 0.35 * n + 0.25 * u + (check && v < 0.3 ? 0.15 : 0);
  rgb[2] = 0.3 + 0.3 * (1 - n) + 0.2 * v * stripes;
}

void ViewToWorld(uint32_t frame, uint32_t camera, double x, double y, uint32_t w, uint32_t h,
                 double* u, double* v) {
  const double scale = 1.0 + 0.03 * camera;
  *u = (x / w - 0.5) / scale + 0.5 + 0.04 * camera + 0.006 * frame;
  *v = (y / h - 0.5) / scale + 0.5 + 0.01 * std::sin(0.7 * camera) + 0.002 * frame;
}

}  // namespace

Image SampleView(uint32_t frame, uint32_t camera, uint32_t width, uint32_t height) {
  Image img;
  img.width = width;
  img.height = height;
  img.channels = 3;
  img.pixels.resize(size_t{width} * height * 3);
  const double shade_cam = 0.92 + 0.08 * std::cos(1.3 * camera);  // per-camera exposure
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x) {
      double u, v, rgb[3];
      ViewToWorld(frame, camera, x, y, width, height, &u, &v);
      Scene(u, v, rgb);
      const double light = shade_cam * (0.85 + 0.15 * (1 - static_cast<double>(y) / height));
      for (int c = 0; c < 3; ++c)
        img.pixels[(size_t{y} * width + x) * 3 + c] =
            static_cast<uint8_t>(std::clamp(rgb[c] * light * 255.0 + 0.5, 0.0, 255.0));
    }
  return img;
}

Image SampleMask(uint32_t frame, uint32_t camera, uint32_t width, uint32_t height) {
  Image img;
  img.width = width;
  img.height = height;
  img.channels = 1;
  img.pixels.resize(size_t{width} * height);
  const double cx = 0.5 + 0.08 * std::sin(0.9 * camera + 0.1 * frame), cy = 0.5;
  const double rx = 0.28 + 0.04 * std::cos(camera), ry = 0.42;
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x) {
      const double dx = (x + 0.5) / width - cx, dy = (y + 0.5) / height - cy;
      img.pixels[size_t{y} * width + x] =
          (dx * dx / (rx * rx) + dy * dy / (ry * ry)) <= 1 ? 255 : 0;
    }
  return img;
}

}  // namespace fvv
