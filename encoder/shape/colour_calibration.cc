#include "encoder/shape/colour_calibration.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <string>

#include "encoder/capture/calibration.h"
#include "encoder/shape/depth_map.h"

namespace fvv {
namespace {

using Eigen::Vector3f;

// The value at which `share` of a histogram's count lies below (bin centres).
double HistogramQuantile(const std::vector<uint32_t>& h, double share, double lo, double step) {
  uint64_t total = 0;
  for (uint32_t n : h) total += n;
  if (total == 0) return 0;
  const double want = share * double(total);
  uint64_t below = 0;
  for (size_t i = 0; i < h.size(); ++i) {
    if (double(below + h[i]) >= want) {
      // Linear within the bin.
      const double within = h[i] ? (want - double(below)) / double(h[i]) : 0.5;
      return lo + step * (double(i) + within);
    }
    below += h[i];
  }
  return lo + step * double(h.size());
}

// The median of |x - centre| over a histogram of x.
double MedianAbsoluteFrom(const std::vector<uint32_t>& h, double centre, double lo, double step) {
  std::vector<std::pair<double, uint32_t>> d;
  d.reserve(h.size());
  uint64_t total = 0;
  for (size_t i = 0; i < h.size(); ++i) {
    if (!h[i]) continue;
    d.emplace_back(std::abs(lo + step * (double(i) + 0.5) - centre), h[i]);
    total += h[i];
  }
  if (total == 0) return 0;
  std::sort(d.begin(), d.end());
  uint64_t below = 0;
  for (const auto& [x, n] : d) {
    below += n;
    if (2 * below >= total) return x;
  }
  return d.back().first;
}

}  // namespace

ColourCalibration::ColourCalibration(std::vector<Camera> cameras, ColourCalibrationOptions options)
    : cameras_(std::move(cameras)), o_(options) {
  const size_t n = cameras_.size();
  histograms_.resize(n < 2 ? 0 : n * (n - 1) / 2);  // one per pair
  for (auto& pair : histograms_) {
    for (auto& h : pair) h.assign(kBins, 0);
  }
  pair_points_.assign(histograms_.size(), 0);
}

size_t ColourCalibration::PairIndex(uint32_t a, uint32_t b) const {
  // Pairs (a < b) in order (0,1) (0,2) .. (0,n-1) (1,2) ..
  const size_t n = cameras_.size();
  return size_t(a) * (2 * n - a - 1) / 2 + (b - a - 1);
}

Status ColourCalibration::AddFrame(const std::vector<std::array<uint32_t, 3>>& triangles,
                                   const std::vector<Vector3f>& positions,
                                   const std::vector<Vector3f>& normals,
                                   const std::vector<Image>& images,
                                   const std::vector<Image>& silhouettes) {
  const size_t n = cameras_.size();
  if (images.size() != n || (!silhouettes.empty() && silhouettes.size() != n)) {
    return InvalidArgument("colour calibration: " + std::to_string(images.size()) + " images for " +
                           std::to_string(n) + " cameras");
  }
  if (normals.size() != positions.size()) {
    return InvalidArgument("colour calibration: a normal per vertex is needed");
  }
  const size_t vertices = positions.size();
  // Per camera and vertex: the colour seen, or level 0 where not seen well.
  std::vector<std::array<float, 3>> seen(n * vertices, {0.f, 0.f, 0.f});
  for (size_t c = 0; c < n; ++c) {
    const Camera& cam = cameras_[c];
    const Image& image = images[c];
    const int w = int(image.width), h = int(image.height);
    if (w != int(cam.width) || h != int(cam.height) || image.pixels.size() != size_t(w) * h * 3) {
      return InvalidArgument("colour calibration: camera \"" + cam.name + "\"'s image is not " +
                             std::to_string(cam.width) + "x" + std::to_string(cam.height) + " RGB");
    }
    const Image* sil = silhouettes.empty() ? nullptr : &silhouettes[c];
    if (sil && !sil->pixels.empty() &&
        (sil->width != image.width || sil->height != image.height ||
         sil->pixels.size() != size_t(w) * h * size_t(std::max(sil->channels, 1)))) {
      return InvalidArgument("colour calibration: camera \"" + cam.name +
                             "\"'s silhouette is not the size of its image");
    }
    const bool use_sil = sil && !sil->pixels.empty();
    const int margin = std::max(1, int(std::lround(o_.inner_margin * std::max(w, h))));
    const int ch = use_sil ? int(sil->channels) : 1;
    auto inside = [&](int x, int y) {
      if (!use_sil) return true;
      auto at = [&](int px, int py) {
        return px >= 0 && py >= 0 && px < w && py < h &&
               sil->pixels[(size_t(py) * w + px) * ch] != 0;
      };
      return at(x, y) && at(x - margin, y) && at(x + margin, y) && at(x, y - margin) &&
             at(x, y + margin);
    };
    const DepthMap depth = RenderDepthMap(triangles, positions, cam);
    const Eigen::Vector3d centre = CameraCentre(cam);
    const double pixel_angle = 1.0 / std::max(cam.fx, cam.fy);
    const uint8_t* src = image.pixels.data();
    for (size_t v = 0; v < vertices; ++v) {
      const Eigen::Vector3d p = positions[v].cast<double>();
      const Eigen::Vector3d view = centre - p;
      const double facing = normals[v].cast<double>().normalized().dot(view) / view.norm();
      if (!(facing >= o_.min_facing)) continue;
      Eigen::Vector2d q;
      double z = 0;
      if (!ProjectPoint(cam, p, &q, &z)) continue;
      const int x = int(std::lround(q.x())), y = int(std::lround(q.y()));
      if (x < 1 || y < 1 || x > w - 2 || y > h - 2) continue;
      const double slope = std::sqrt(std::max(0.0, 1.0 - facing * facing)) / facing;
      if (z > depth.depth[size_t(y) * w + x] + o_.depth_tolerance + z * pixel_angle * slope) {
        continue;
      }
      if (!inside(x, y)) continue;
      // The 3x3 pixels' mean: less of the sensor's noise.
      std::array<float, 3> sum{0.f, 0.f, 0.f};
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const uint8_t* px = src + (size_t(y + dy) * w + (x + dx)) * 3;
          for (int k = 0; k < 3; ++k) sum[k] += px[k];
        }
      }
      bool usable = true;
      for (int k = 0; k < 3; ++k) {
        sum[k] /= 9.f;
        usable = usable && sum[k] >= o_.min_level && sum[k] <= o_.max_level;
      }
      if (usable) seen[c * vertices + v] = sum;
    }
  }
  const double step = 2 * kRange / kBins;
  for (size_t v = 0; v < vertices; ++v) {
    for (uint32_t a = 0; a < n; ++a) {
      const auto& ca = seen[a * vertices + v];
      if (ca[0] <= 0) continue;
      for (uint32_t b = a + 1; b < n; ++b) {
        const auto& cb = seen[b * vertices + v];
        if (cb[0] <= 0) continue;
        const size_t pair = PairIndex(a, b);
        for (int k = 0; k < 3; ++k) {
          const double d = std::log(double(ca[k]) / double(cb[k]));
          const int bin = std::clamp(int(std::floor((d + kRange) / step)), 0, kBins - 1);
          ++histograms_[pair][k][bin];
        }
        ++pair_points_[pair];
      }
    }
  }
  ++frames_;
  return Status::Ok();
}

StatusOr<ColourCalibrationResult> ColourCalibration::Solve() const {
  const uint32_t n = uint32_t(cameras_.size());
  const double step = 2 * kRange / kBins;
  ColourCalibrationResult r;
  r.gains.assign(n, {1.0, 1.0, 1.0});
  r.points.assign(n, 0);
  r.calibrated.assign(n, false);
  std::vector<ColourPair> used;
  for (uint32_t a = 0; a < n; ++a) {
    for (uint32_t b = a + 1; b < n; ++b) {
      const size_t i = PairIndex(a, b);
      ColourPair p;
      p.a = a, p.b = b, p.points = pair_points_[i];
      for (int k = 0; k < 3; ++k) {
        p.ratio[k] = std::exp(HistogramQuantile(histograms_[i][k], 0.5, -kRange, step));
      }
      r.pairs.push_back(p);
      if (p.points < o_.min_pair_points) continue;
      used.push_back(p);
      r.points[a] += p.points, r.points[b] += p.points;
      r.calibrated[a] = r.calibrated[b] = true;
    }
  }
  if (used.empty()) {
    return InvalidArgument("colour calibration: no two cameras see enough of the same surface (" +
                           std::to_string(o_.min_pair_points) + " vertex-frames) in " +
                           std::to_string(frames_) + " frame(s)");
  }
  // The cameras joined by shared surface, the largest such group alone: two
  // groups that share nothing have no common colour.
  std::vector<uint32_t> group(n);
  for (uint32_t c = 0; c < n; ++c) group[c] = c;
  const auto root = [&](uint32_t c) {
    while (group[c] != c) c = group[c] = group[group[c]];
    return c;
  };
  for (const ColourPair& p : used) group[root(p.a)] = root(p.b);
  std::vector<uint64_t> group_points(n, 0);
  for (const ColourPair& p : used) group_points[root(p.a)] += p.points;
  const uint32_t largest =
      uint32_t(std::max_element(group_points.begin(), group_points.end()) - group_points.begin());
  used.erase(std::remove_if(used.begin(), used.end(),
                            [&](const ColourPair& p) { return root(p.a) != largest; }),
             used.end());
  for (uint32_t c = 0; c < n; ++c) {
    if (root(c) != largest) r.calibrated[c] = false, r.points[c] = 0;
  }
  // Per channel: x_c = log of camera c's response; x_a - x_b = log ratio of
  // the pair, weighted by the square root of its points; the calibrated
  // cameras' mean is 0. The gain undoes the response.
  std::vector<uint32_t> index(n, UINT32_MAX);
  uint32_t m = 0;
  for (uint32_t c = 0; c < n; ++c) {
    if (r.calibrated[c]) index[c] = m++;
  }
  std::array<Eigen::VectorXd, 3> x;
  for (int k = 0; k < 3; ++k) {
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(used.size() + 1, m);
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(used.size() + 1);
    for (size_t e = 0; e < used.size(); ++e) {
      const double wgt = std::sqrt(double(used[e].points));
      A(e, index[used[e].a]) = wgt;
      A(e, index[used[e].b]) = -wgt;
      rhs(e) = wgt * std::log(used[e].ratio[k]);
    }
    A.row(used.size()).setConstant(1.0);
    x[k] = A.colPivHouseholderQr().solve(rhs);
    for (uint32_t c = 0; c < n; ++c) {
      if (r.calibrated[c]) r.gains[c][k] = std::exp(-x[k](index[c]));
    }
  }
  // How far the cameras differ at shared points, before and after.
  double before = 0, after = 0, weight = 0;
  for (const ColourPair& p : used) {
    const size_t i = PairIndex(p.a, p.b);
    for (int k = 0; k < 3; ++k) {
      const double predicted = x[k](index[p.a]) - x[k](index[p.b]);
      before += double(p.points) * MedianAbsoluteFrom(histograms_[i][k], 0.0, -kRange, step) / 3;
      after +=
          double(p.points) * MedianAbsoluteFrom(histograms_[i][k], predicted, -kRange, step) / 3;
    }
    weight += double(p.points);
  }
  r.difference_before = before / weight;
  r.difference_after = after / weight;
  return r;
}

}  // namespace fvv
