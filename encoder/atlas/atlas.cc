#include "encoder/atlas/atlas.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <queue>

namespace fvv {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

Vector3d Pos(const Mesh& m, uint32_t v) {
  return Vector3d(m.positions[v][0], m.positions[v][1], m.positions[v][2]);
}

struct Chart {
  int segment;
  std::vector<uint32_t> tris;  // source triangles
  Vector3d normal, u, v;
  Vector2d lo, hi;  // projected extent, metres
};

// Shelf packing of rectangles (w, h in texels) into a square of side `size`;
// returns false when they do not fit.
bool Pack(const std::vector<std::pair<uint32_t, uint32_t>>& rects, uint32_t size,
          std::vector<std::pair<uint32_t, uint32_t>>* where) {
  std::vector<size_t> order(rects.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return rects[a].second != rects[b].second ? rects[a].second > rects[b].second : a < b;
  });
  where->assign(rects.size(), {0, 0});
  uint32_t x = 0, y = 0, shelf = 0;
  for (size_t i : order) {
    const auto [w, h] = rects[i];
    if (w > size || h > size) return false;
    if (x + w > size) {
      y += shelf;
      x = 0;
      shelf = 0;
    }
    if (y + h > size) return false;
    (*where)[i] = {x, y};
    x += w;
    shelf = std::max(shelf, h);
  }
  return true;
}

}  // namespace

StatusOr<Atlas> BuildAtlas(const Mesh& m, const AtlasOptions& o) {
  if (o.size < 16 || o.size > 4096) return InvalidArgument("atlas: size must be 16..4096");
  if (!(o.max_normal_deviation > 0 && o.max_normal_deviation < 89)) {
    return InvalidArgument("atlas: normal deviation must be in (0, 89) degrees");
  }
  if (m.triangles.empty()) return InvalidArgument("atlas: the mesh has no triangles");
  const size_t nt = m.triangles.size();
  // Triangle normals and areas; adjacency across edges of welded positions
  // (the model duplicates vertices on its own seams).
  std::vector<Vector3d> tn(nt);
  std::vector<double> area(nt);
  std::map<std::array<float, 3>, uint32_t> weld;
  std::vector<uint32_t> welded(m.positions.size());
  for (size_t v = 0; v < m.positions.size(); ++v)
    welded[v] = weld.emplace(m.positions[v], weld.size()).first->second;
  std::map<std::pair<uint32_t, uint32_t>, std::vector<uint32_t>> edges;
  for (size_t t = 0; t < nt; ++t) {
    const auto& tri = m.triangles[t];
    const Vector3d c = (Pos(m, tri[1]) - Pos(m, tri[0])).cross(Pos(m, tri[2]) - Pos(m, tri[0]));
    area[t] = 0.5 * c.norm();
    tn[t] = c.norm() > 0 ? Vector3d(c.normalized()) : Vector3d::UnitZ();
    for (int e = 0; e < 3; ++e) {
      uint32_t a = welded[tri[e]], b = welded[tri[(e + 1) % 3]];
      if (a > b) std::swap(a, b);
      edges[{a, b}].push_back(uint32_t(t));
    }
  }
  std::vector<std::vector<uint32_t>> neighbours(nt);
  for (const auto& [edge, list] : edges) {
    for (uint32_t a : list) {
      for (uint32_t b : list) {
        if (a != b) neighbours[a].push_back(b);
      }
    }
  }

  // Grow charts: breadth first from a seed, within the seed's segment, while
  // each new triangle stays close to the chart's area-weighted average normal.
  const double limit = std::cos(o.max_normal_deviation * 3.14159265358979323846 / 180);
  std::vector<int> chart_of(nt, -1);
  std::vector<Chart> charts;
  for (size_t seed = 0; seed < nt; ++seed) {
    if (chart_of[seed] >= 0) continue;
    Chart c;
    c.segment = m.segments.empty() ? 0 : m.segments[m.triangles[seed][0]];
    Vector3d sum = Vector3d::Zero();
    std::queue<uint32_t> q;
    q.push(uint32_t(seed));
    chart_of[seed] = int(charts.size());
    while (!q.empty()) {
      const uint32_t t = q.front();
      q.pop();
      c.tris.push_back(t);
      sum += area[t] * tn[t];
      for (uint32_t n : neighbours[t]) {
        if (chart_of[n] >= 0) continue;
        if (!m.segments.empty() && m.segments[m.triangles[n][0]] != c.segment) continue;
        if (tn[n].dot(sum.normalized()) < limit) continue;
        chart_of[n] = int(charts.size());
        q.push(n);
      }
    }
    c.normal = sum.norm() > 0 ? Vector3d(sum.normalized()) : tn[seed];
    charts.push_back(std::move(c));
  }

  // Project each chart onto the plane of its normal, axes along the principal
  // directions of its projected vertices (tighter rectangles).
  for (Chart& c : charts) {
    Vector3d a = std::abs(c.normal.x()) < 0.9 ? Vector3d::UnitX() : Vector3d::UnitY();
    Vector3d u = c.normal.cross(a).normalized(), v = c.normal.cross(u);
    Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
    Vector2d mean = Vector2d::Zero();
    int count = 0;
    for (uint32_t t : c.tris) {
      for (uint32_t vi : m.triangles[t]) {
        const Vector3d p = Pos(m, vi);
        mean += Vector2d(p.dot(u), p.dot(v));
        ++count;
      }
    }
    mean /= count;
    for (uint32_t t : c.tris) {
      for (uint32_t vi : m.triangles[t]) {
        const Vector3d p = Pos(m, vi);
        const Vector2d d = Vector2d(p.dot(u), p.dot(v)) - mean;
        cov += d * d.transpose();
      }
    }
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(cov);
    const Vector2d major = eig.eigenvectors().col(1);
    const Vector3d u2 = (major.x() * u + major.y() * v).normalized();
    c.u = u2;
    c.v = c.normal.cross(u2);
    c.lo = Vector2d::Constant(1e30), c.hi = Vector2d::Constant(-1e30);
    for (uint32_t t : c.tris) {
      for (uint32_t vi : m.triangles[t]) {
        const Vector3d p = Pos(m, vi);
        const Vector2d q(p.dot(c.u), p.dot(c.v));
        c.lo = c.lo.cwiseMin(q), c.hi = c.hi.cwiseMax(q);
      }
    }
  }

  // The largest density (texels per metre) whose packing fits: bisection.
  double total = 0;
  for (double a : area) total += a;
  double lo = 0, hi = 4.0 * o.size / std::sqrt(total);
  std::vector<std::pair<uint32_t, uint32_t>> rects(charts.size()), where, best_where;
  auto rects_at = [&](double s) {
    for (size_t i = 0; i < charts.size(); ++i) {
      const Vector2d e = (charts[i].hi - charts[i].lo) * s;
      rects[i] = {uint32_t(std::ceil(e.x())) + 1 + 2 * o.gutter,
                  uint32_t(std::ceil(e.y())) + 1 + 2 * o.gutter};
    }
  };
  for (int it = 0; it < 40; ++it) {
    const double mid = 0.5 * (lo + hi);
    rects_at(mid);
    if (Pack(rects, o.size, &where)) {
      lo = mid;
      best_where = where;
    } else {
      hi = mid;
    }
  }
  if (best_where.empty() || lo <= 0) {
    return LimitExceeded("atlas: " + std::to_string(charts.size()) + " charts do not fit a " +
                         std::to_string(o.size) + " atlas with " + std::to_string(o.gutter) +
                         "-texel gutters");
  }
  rects_at(lo);

  Atlas atlas;
  atlas.size = o.size;
  atlas.texels_per_metre = lo;
  Mesh& out = atlas.mesh;
  for (size_t ci = 0; ci < charts.size(); ++ci) {
    const Chart& c = charts[ci];
    AtlasChart ac;
    ac.segment = c.segment;
    ac.normal = c.normal;
    ac.x = best_where[ci].first, ac.y = best_where[ci].second;
    ac.width = rects[ci].first, ac.height = rects[ci].second;
    std::map<uint32_t, uint32_t> local;  // source vertex -> atlas vertex in this chart
    for (uint32_t t : c.tris) {
      std::array<uint32_t, 3> nt3;
      for (int k = 0; k < 3; ++k) {
        const uint32_t src = m.triangles[t][k];
        auto it = local.find(src);
        if (it == local.end()) {
          const uint32_t id = uint32_t(out.positions.size());
          out.positions.push_back(m.positions[src]);
          if (!m.normals.empty()) out.normals.push_back(m.normals[src]);
          if (!m.joints.empty()) out.joints.push_back(m.joints[src]);
          if (!m.weights.empty()) out.weights.push_back(m.weights[src]);
          if (!m.segments.empty()) out.segments.push_back(m.segments[src]);
          const Vector3d p = Pos(m, src);
          const Vector2d q = (Vector2d(p.dot(c.u), p.dot(c.v)) - c.lo) * lo;
          out.uvs.push_back({float((ac.x + o.gutter + 0.5 + q.x()) / o.size),
                             float((ac.y + o.gutter + 0.5 + q.y()) / o.size)});
          atlas.source_vertex.push_back(src);
          it = local.emplace(src, id).first;
        }
        nt3[k] = it->second;
      }
      ac.triangles.push_back(uint32_t(out.triangles.size()));
      out.triangles.push_back(nt3);
    }
    atlas.charts.push_back(std::move(ac));
  }
  return atlas;
}

}  // namespace fvv
