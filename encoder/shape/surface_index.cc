#include "encoder/shape/surface_index.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fvv {

Eigen::Vector3d ClosestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                       const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  // Voronoi regions of the vertices, edges and face (Ericson, Real-Time
  // Collision Detection, 5.1.5).
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / std::max(d1 - d3, 1e-300));
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / std::max(d2 - d6, 1e-300));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    return b + (c - b) * ((d4 - d3) / std::max((d4 - d3) + (d5 - d6), 1e-300));
  }
  const double sum = va + vb + vc;
  if (!(std::abs(sum) > 1e-300)) return a;  // degenerate: its first point
  return a + ab * (vb / sum) + ac * (vc / sum);
}

SurfaceIndex::SurfaceIndex(const std::vector<Eigen::Vector3f>& positions,
                           const std::vector<std::array<uint32_t, 3>>& triangles, double cell) {
  for (const auto& p : positions) points_.push_back(p.cast<double>());
  triangles_ = triangles;
  Build(cell);
}

SurfaceIndex SurfaceIndex::Points(const std::vector<Eigen::Vector3d>& points, double cell) {
  SurfaceIndex index;
  index.points_ = points;
  for (uint32_t i = 0; i < points.size(); ++i) index.triangles_.push_back({i, i, i});
  index.Build(cell);
  return index;
}

void SurfaceIndex::Build(double cell) {
  cell_ = cell;
  if (triangles_.empty()) return;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::max());
  Eigen::Vector3d hi = -lo;
  for (const auto& t : triangles_) {
    for (uint32_t i : t) lo = lo.cwiseMin(points_[i]), hi = hi.cwiseMax(points_[i]);
  }
  origin_ = lo;
  for (int k = 0; k < 3; ++k) {
    // Bounded: a cell at least 1/512 of the extent.
    cell_ = std::max(cell_, (hi[k] - lo[k]) / 512);
  }
  for (int k = 0; k < 3; ++k) dims_[k] = int((hi[k] - lo[k]) / cell_) + 1;
  const auto cell_of = [&](const Eigen::Vector3d& p, int k) {
    return std::clamp(int((p[k] - origin_[k]) / cell_), 0, dims_[k] - 1);
  };
  const size_t cells = size_t(dims_[0]) * dims_[1] * dims_[2];
  std::vector<uint32_t> count(cells + 1, 0);
  // Two sweeps: count, then fill (compressed rows).
  for (int sweep = 0; sweep < 2; ++sweep) {
    if (sweep == 1) {
      start_.assign(cells + 1, 0);
      for (size_t i = 0; i < cells; ++i) start_[i + 1] = start_[i] + count[i];
      entries_.resize(start_[cells]);
      std::fill(count.begin(), count.end(), 0);
    }
    for (uint32_t t = 0; t < triangles_.size(); ++t) {
      std::array<int, 3> a, b;
      for (int k = 0; k < 3; ++k) {
        const double mn = std::min({points_[triangles_[t][0]][k], points_[triangles_[t][1]][k],
                                    points_[triangles_[t][2]][k]});
        const double mx = std::max({points_[triangles_[t][0]][k], points_[triangles_[t][1]][k],
                                    points_[triangles_[t][2]][k]});
        a[k] = cell_of(Eigen::Vector3d::Constant(mn), k);
        b[k] = cell_of(Eigen::Vector3d::Constant(mx), k);
      }
      for (int z = a[2]; z <= b[2]; ++z) {
        for (int y = a[1]; y <= b[1]; ++y) {
          for (int x = a[0]; x <= b[0]; ++x) {
            const size_t c = (size_t(z) * dims_[1] + y) * dims_[0] + x;
            if (sweep == 1) entries_[start_[c] + count[c]] = t;
            ++count[c];
          }
        }
      }
    }
  }
}

double SurfaceIndex::Nearest(const Eigen::Vector3d& p, Eigen::Vector3d* closest) const {
  double best = std::numeric_limits<double>::infinity();
  if (triangles_.empty()) return best;
  std::array<int, 3> home;
  for (int k = 0; k < 3; ++k) {
    home[k] = std::clamp(int(std::floor((p[k] - origin_[k]) / cell_)), 0, dims_[k] - 1);
  }
  const int max_ring = std::max({dims_[0], dims_[1], dims_[2]});
  Eigen::Vector3d best_point = p;
  for (int r = 0; r <= max_ring; ++r) {
    for (int z = home[2] - r; z <= home[2] + r; ++z) {
      if (z < 0 || z >= dims_[2]) continue;
      for (int y = home[1] - r; y <= home[1] + r; ++y) {
        if (y < 0 || y >= dims_[1]) continue;
        for (int x = home[0] - r; x <= home[0] + r; ++x) {
          if (x < 0 || x >= dims_[0]) continue;
          // Only the ring's shell: the inside was searched before.
          if (std::max({std::abs(x - home[0]), std::abs(y - home[1]), std::abs(z - home[2])}) !=
              r) {
            continue;
          }
          const size_t c = (size_t(z) * dims_[1] + y) * dims_[0] + x;
          for (uint32_t e = start_[c]; e < start_[c + 1]; ++e) {
            const auto& t = triangles_[entries_[e]];
            const Eigen::Vector3d q =
                ClosestPointOnTriangle(p, points_[t[0]], points_[t[1]], points_[t[2]]);
            const double d = (q - p).squaredNorm();
            if (d < best) best = d, best_point = q;
          }
        }
      }
    }
    // Cells of the next ring lie at least r cells from the home cell (and the
    // point, or its projection onto the grid's box, is inside that cell).
    if (best <= (r * cell_) * (r * cell_)) break;
  }
  if (closest) *closest = best_point;
  return std::sqrt(best);
}

DistanceSummary SummariseDistances(const std::vector<Eigen::Vector3d>& points,
                                   const SurfaceIndex& surface) {
  DistanceSummary s;
  std::vector<double> d;
  d.reserve(points.size());
  for (const auto& p : points) d.push_back(surface.Nearest(p));
  s.count = d.size();
  if (d.empty()) return s;
  double sum = 0;
  for (double x : d) sum += x;
  s.mean = sum / double(d.size());
  std::sort(d.begin(), d.end());
  s.p95 = d[std::min(d.size() - 1, size_t(0.95 * double(d.size())))];
  s.max = d.back();
  return s;
}

}  // namespace fvv
