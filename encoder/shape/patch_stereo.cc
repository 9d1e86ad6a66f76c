#include "encoder/shape/patch_stereo.h"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <utility>

#include "encoder/capture/calibration.h"

namespace fvv {

using Eigen::Vector3d;

float GreyImage::At(const Eigen::Vector2d& q) const {
  if (!(q.x() >= 0 && q.y() >= 0 && q.x() <= width - 1 && q.y() <= height - 1)) return NAN;
  const int x0 = std::min(int(q.x()), width - 2 < 0 ? 0 : width - 2);
  const int y0 = std::min(int(q.y()), height - 2 < 0 ? 0 : height - 2);
  const int x1 = std::min(x0 + 1, width - 1), y1 = std::min(y0 + 1, height - 1);
  const float fx = float(q.x() - x0), fy = float(q.y() - y0);
  const float* r0 = &pixels[size_t(y0) * width];
  const float* r1 = &pixels[size_t(y1) * width];
  return (1 - fy) * ((1 - fx) * r0[x0] + fx * r0[x1]) + fy * ((1 - fx) * r1[x0] + fx * r1[x1]);
}

GreyImage Grey(const Image& rgb, int factor) {
  GreyImage g;
  factor = std::max(1, factor);
  const int ch = int(rgb.channels);
  g.width = int(rgb.width) / factor;
  g.height = int(rgb.height) / factor;
  g.pixels.assign(size_t(g.width) * g.height, 0.0f);
  if (ch < 3) return g;
  const float scale = 1.0f / float(factor * factor);
  for (int y = 0; y < g.height; ++y) {
    for (int x = 0; x < g.width; ++x) {
      float sum = 0;
      for (int dy = 0; dy < factor; ++dy) {
        const uint8_t* row = &rgb.pixels[(size_t(y * factor + dy) * rgb.width + x * factor) * ch];
        for (int dx = 0; dx < factor; ++dx) {
          const uint8_t* px = row + dx * ch;
          sum += 0.299f * px[0] + 0.587f * px[1] + 0.114f * px[2];
        }
      }
      g.pixels[size_t(y) * g.width + x] = sum * scale;
    }
  }
  return g;
}

double Ncc(const std::vector<float>& a, const std::vector<float>& b) {
  double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
  const double n = double(a.size());
  for (size_t i = 0; i < a.size(); ++i) {
    if (std::isnan(a[i]) || std::isnan(b[i])) return NAN;
    sa += a[i], sb += b[i], saa += a[i] * a[i], sbb += b[i] * b[i], sab += a[i] * b[i];
  }
  const double va = saa - sa * sa / n, vb = sbb - sb * sb / n;
  if (!(va > 1e-6 && vb > 1e-6)) return NAN;
  return (sab - sa * sb / n) / std::sqrt(va * vb);
}

LocalSurface FitSurface(const Vector3d& p, const Vector3d& normal,
                        const std::vector<uint32_t>& ring,
                        const std::vector<Eigen::Vector3f>& positions) {
  LocalSurface s;
  s.u = normal.unitOrthogonal();
  s.w = normal.cross(s.u);
  Eigen::Matrix3d ata = Eigen::Matrix3d::Zero();
  Vector3d atb = Vector3d::Zero();
  for (uint32_t nb : ring) {
    const Vector3d d = positions[nb].cast<double>() - p;
    const double x = d.dot(s.u), y = d.dot(s.w), h = d.dot(normal);
    const Vector3d row(x * x, x * y, y * y);
    ata += row * row.transpose();
    atb += row * h;
  }
  if (ring.size() >= 3 && std::abs(ata.determinant()) > 1e-24) {
    const Vector3d abc = ata.ldlt().solve(atb);
    if (abc.allFinite()) s.a = abc[0], s.b = abc[1], s.c = abc[2];
  }
  return s;
}

StereoTarget MatchAlongKeyRay(const StereoViews& views, const std::vector<uint8_t>& visible,
                              const Vector3d& p, const Vector3d& normal,
                              const LocalSurface& surface, double range,
                              const PatchStereoOptions& o) {
  StereoTarget out;
  const size_t m = views.cameras.size();
  int key = -1;
  double best_facing = o.key_facing;
  std::vector<double> facing(m, -1);
  for (size_t c = 0; c < m && c < visible.size(); ++c) {
    if (!visible[c]) continue;
    facing[c] = normal.dot((views.centres[c] - p).normalized());
    if (facing[c] > best_facing) best_facing = facing[c], key = int(c);
  }
  if (key < 0) return out;
  const Vector3d key_dir = (views.centres[key] - p).normalized();
  std::vector<std::pair<double, int>> adjacent;
  for (size_t c = 0; c < m; ++c) {
    if (int(c) == key || facing[c] < 0.2) continue;
    const double angle =
        std::acos(std::clamp(key_dir.dot((views.centres[c] - p).normalized()), -1.0, 1.0));
    if (angle < o.max_angle) adjacent.emplace_back(angle, int(c));
  }
  if (adjacent.empty() || int(adjacent.size()) < o.min_neighbours) return out;
  std::sort(adjacent.begin(), adjacent.end());
  if (adjacent.size() > 2) adjacent.resize(2);
  // The patch: a square over the local surface, about one key-view pixel
  // per sample.
  const Camera& kc = views.cameras[key];
  const double depth = (p - views.centres[key]).norm();
  const double spacing = depth / std::max(kc.fx, kc.fy) / std::max(best_facing, 0.5);
  const int r = o.patch_radius, side = 2 * r + 1;
  std::vector<Vector3d> offsets;
  for (int y = -r; y <= r; ++y) {
    for (int x = -r; x <= r; ++x) {
      const double sx = x * spacing, sy = y * spacing;
      offsets.push_back(sx * surface.u + sy * surface.w +
                        (surface.a * sx * sx + surface.b * sx * sy + surface.c * sy * sy) * normal);
    }
  }
  std::vector<float> key_patch(size_t(side) * side), other(key_patch.size());
  const auto sample = [&](int camera, const Vector3d& centre, std::vector<float>* patch) {
    for (size_t i = 0; i < offsets.size(); ++i) {
      Eigen::Vector2d q;
      (*patch)[i] = ProjectPoint(views.cameras[camera], centre + offsets[i], &q)
                        ? views.grey[camera].At(q)
                        : NAN;
    }
  };
  // The key patch's contrast decides whether there is anything to match.
  sample(key, p, &key_patch);
  double s = 0, ss = 0;
  for (float k : key_patch) {
    if (std::isnan(k)) return out;
    s += k, ss += double(k) * k;
  }
  const double n = double(key_patch.size());
  if (std::sqrt(std::max(0.0, ss / n - (s / n) * (s / n))) < o.min_patch_std) return out;
  constexpr int kSteps = 16;
  const Vector3d ray = -key_dir;  // from the key camera through the point
  double scores[kSteps + 1];
  for (int i = 0; i <= kSteps; ++i) {
    const Vector3d q = p + ray * (-range + 2 * range * i / kSteps);
    sample(key, q, &key_patch);
    double sum = 0;
    int count = 0;
    for (const auto& a : adjacent) {
      sample(a.second, q, &other);
      const double c = Ncc(key_patch, other);
      if (!std::isnan(c)) sum += c, ++count;
    }
    scores[i] = count ? sum / count : -1;
  }
  const int best = int(std::max_element(scores, scores + kSteps + 1) - scores);
  // A match at either end of the range may lie beyond it: not trusted.
  if (best == 0 || best == kSteps || scores[best] < o.min_ncc) return out;
  // Sub-step peak by a parabola through the best score and its neighbours.
  const double l = scores[best - 1], c = scores[best], rr = scores[best + 1];
  const double denom = l - 2 * c + rr;
  const double offset = denom < 0 ? std::clamp(0.5 * (l - rr) / denom, -0.5, 0.5) : 0.0;
  const double t = -range + 2 * range * (best + offset) / kSteps;
  out.valid = true;
  out.point = p + ray * t;
  out.score = c;
  return out;
}

}  // namespace fvv
