#include "player/playback/depth_map_triangles.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#include <limits>
#include <numeric>
#include <unordered_map>

#include "container/geometric_visibility.h"

namespace fvv {
namespace {

using Vec = glm::dvec3;

// The sum of weight * (n . p + d)^2 over planes, and the sum of weights.
struct Quadric {
  double xx = 0, xy = 0, xz = 0, yy = 0, yz = 0, zz = 0, x = 0, y = 0, z = 0, c = 0, w = 0;

  void AddPlane(const Vec& n, double d, double weight) {
    xx += weight * n[0] * n[0];
    xy += weight * n[0] * n[1];
    xz += weight * n[0] * n[2];
    yy += weight * n[1] * n[1];
    yz += weight * n[1] * n[2];
    zz += weight * n[2] * n[2];
    x += weight * n[0] * d;
    y += weight * n[1] * d;
    z += weight * n[2] * d;
    c += weight * d * d;
    w += weight;
  }
  void Add(const Quadric& o) {
    xx += o.xx, xy += o.xy, xz += o.xz, yy += o.yy, yz += o.yz, zz += o.zz;
    x += o.x, y += o.y, z += o.z, c += o.c, w += o.w;
  }
  // The mean squared distance of p to the planes (0 without any).
  double MeanSquared(const Vec& p) const {
    if (!(w > 0)) return 0;
    const double e = xx * p[0] * p[0] + yy * p[1] * p[1] + zz * p[2] * p[2] +
                     2 * (xy * p[0] * p[1] + xz * p[0] * p[2] + yz * p[1] * p[2]) +
                     2 * (x * p[0] + y * p[1] + z * p[2]) + c;
    return std::max(0.0, e) / w;
  }
};

// Moving vertex `from` onto vertex `to`, at `cost`. Ordered cheapest first,
// ties by the vertices' indices: a total order, so every sort agrees.
struct Collapse {
  double cost;
  uint32_t from, to;
};
bool Cheaper(const Collapse& a, const Collapse& b) {
  if (a.cost != b.cost) return a.cost < b.cost;
  if (a.from != b.from) return a.from < b.from;
  return a.to < b.to;
}

class Simplifier {
 public:
  Simplifier(const float* positions, uint32_t vertex_count, std::vector<uint32_t> corners)
      : corners_(std::move(corners)),
        position_(vertex_count),
        quadric_(vertex_count),
        triangles_of_(vertex_count),
        locked_(vertex_count, 0),
        gone_(vertex_count, 0),
        seen_(vertex_count, 0),
        common_(vertex_count, 0) {
    for (uint32_t v = 0; v < vertex_count; ++v) {
      position_[v] =
          Vec(positions[size_t{v} * 3], positions[size_t{v} * 3 + 1], positions[size_t{v} * 3 + 2]);
    }
    const uint32_t triangles = uint32_t(corners_.size() / 3);
    alive_.assign(triangles, 1);
    live_ = triangles;
    std::unordered_map<uint64_t, uint32_t> edge_uses;
    for (uint32_t t = 0; t < triangles; ++t) {
      const uint32_t* c = &corners_[size_t{t} * 3];
      const Vec n =
          glm::cross(position_[c[1]] - position_[c[0]], position_[c[2]] - position_[c[0]]);
      const double length = std::sqrt(glm::dot(n, n));
      for (int k = 0; k < 3; ++k) {
        triangles_of_[c[k]].push_back(t);
        const uint32_t a = std::min(c[k], c[(k + 1) % 3]), b = std::max(c[k], c[(k + 1) % 3]);
        ++edge_uses[uint64_t{a} << 32 | b];
      }
      if (!(length > 0)) continue;
      const Vec unit = n / length;
      const double d = -glm::dot(unit, position_[c[0]]);
      for (int k = 0; k < 3; ++k) quadric_[c[k]].AddPlane(unit, d, length / 2);
    }
    // An edge of one triangle (an open border) or of more (a seam of
    // surfaces) keeps its vertices where they are.
    for (const auto& [edge, uses] : edge_uses) {
      if (uses == 2) continue;
      locked_[uint32_t(edge >> 32)] = 1;
      locked_[uint32_t(edge & 0xffffffffu)] = 1;
    }
  }

  // Collapses until at most `target` triangles live or none costs at most
  // `bound` (a mean squared distance), in rounds. Each vertex offers its
  // cheapest allowed collapse (kept from round to round until a collapse
  // changes its neighbourhood); of the offers, the cheaper half is taken,
  // cheapest first, each where no collapse of the round has touched its two
  // vertices' neighbourhoods yet (so its cost still holds). A heap of every
  // vertex's offer, renewed at each change, spent its time missing the cache
  // on large models; rounds sort instead.
  void Run(uint32_t target, double bound) {
    const uint32_t n = uint32_t(triangles_of_.size());
    std::vector<uint32_t> touched(n, 0);
    std::vector<uint8_t> stale(n, 1);
    std::vector<Collapse> offer(n), offers, choices;
    for (uint32_t v = 0; v < n; ++v) offer[v] = {0, v, v};  // to == from: none
    for (uint32_t round = 1; live_ > target; ++round) {
      offers.clear();
      for (uint32_t v = 0; v < n; ++v) {
        if (locked_[v] || gone_[v] || triangles_of_[v].empty()) continue;
        if (stale[v]) {
          stale[v] = 0;
          offer[v] = {0, v, v};
          choices.clear();
          for (uint32_t to : Neighbours(v)) {
            const Collapse c{Cost(v, to), v, to};
            if (c.cost <= bound) choices.push_back(c);
          }
          std::sort(choices.begin(), choices.end(), Cheaper);
          for (const Collapse& c : choices) {
            if (Allowed(c.from, c.to)) {
              offer[v] = c;
              break;
            }
          }
        }
        if (offer[v].to != v) offers.push_back(offer[v]);
      }
      std::sort(offers.begin(), offers.end(), Cheaper);
      offers.resize((offers.size() + 1) / 2);  // the cheaper half: near the greedy order
      bool any = false;
      for (const Collapse& c : offers) {
        if (live_ <= target) break;
        if (touched[c.from] == round || touched[c.to] == round) continue;
        if (!Allowed(c.from, c.to)) {  // its neighbours' collapses changed that
          stale[c.from] = 1;
          continue;
        }
        Apply(c.from, c.to);
        any = true;
        touched[c.to] = round;
        stale[c.to] = 1;
        for (uint32_t w : Neighbours(c.to)) {
          touched[w] = round;
          stale[w] = 1;
        }
      }
      if (!any) break;
    }
  }

  std::vector<uint32_t> Triangles() const {
    std::vector<uint32_t> out;
    out.reserve(size_t{live_} * 3);
    for (size_t t = 0; t < alive_.size(); ++t) {
      if (alive_[t]) out.insert(out.end(), &corners_[t * 3], &corners_[t * 3] + 3);
    }
    return out;
  }

 private:
  double Cost(uint32_t from, uint32_t to) const {
    Quadric q = quadric_[from];
    q.Add(quadric_[to]);
    return q.MeanSquared(position_[to]);
  }

  // The distinct vertices sharing a triangle with v, in index order, in
  // `neighbours_` (one buffer for every call: this runs for each collapse).
  const std::vector<uint32_t>& Neighbours(uint32_t v) {
    neighbours_.clear();
    for (uint32_t t : triangles_of_[v]) {
      for (int k = 0; k < 3; ++k) {
        if (corners_[size_t{t} * 3 + k] != v) neighbours_.push_back(corners_[size_t{t} * 3 + k]);
      }
    }
    std::sort(neighbours_.begin(), neighbours_.end());
    neighbours_.erase(std::unique(neighbours_.begin(), neighbours_.end()), neighbours_.end());
    return neighbours_;
  }

  bool Contains(uint32_t t, uint32_t v) const {
    const uint32_t* c = &corners_[size_t{t} * 3];
    return c[0] == v || c[1] == v || c[2] == v;
  }

  // Whether moving `from` onto `to` keeps the surface a surface: the two
  // share no neighbour but the corners of their shared triangles (else the
  // surface would touch itself), and no triangle turns over or flattens.
  bool Allowed(uint32_t from, uint32_t to) {
    ++stamp_;
    for (uint32_t t : triangles_of_[to]) {
      for (int k = 0; k < 3; ++k) seen_[corners_[size_t{t} * 3 + k]] = stamp_;
    }
    uint32_t shared = 0, common = 0;
    for (uint32_t t : triangles_of_[from]) {
      const uint32_t* c = &corners_[size_t{t} * 3];
      if (Contains(t, to)) ++shared;
      for (int k = 0; k < 3; ++k) {
        const uint32_t w = c[k];
        if (w == from || w == to || seen_[w] != stamp_ || common_[w] == stamp_) continue;
        common_[w] = stamp_;
        ++common;
      }
    }
    if (shared == 0 || common != shared) return false;
    for (uint32_t t : triangles_of_[from]) {
      if (Contains(t, to)) continue;
      const uint32_t* c = &corners_[size_t{t} * 3];
      Vec p[3], q[3];
      for (int k = 0; k < 3; ++k) {
        p[k] = position_[c[k]];
        q[k] = c[k] == from ? position_[to] : p[k];
      }
      const Vec before = glm::cross(p[1] - p[0], p[2] - p[0]);
      const Vec after = glm::cross(q[1] - q[0], q[2] - q[0]);
      const double dot = glm::dot(before, after);
      if (!(dot > 0) || dot * dot <= 0.04 * glm::dot(before, before) * glm::dot(after, after)) {
        return false;
      }
    }
    return true;
  }

  void Apply(uint32_t from, uint32_t to) {
    for (uint32_t t : triangles_of_[from]) {
      uint32_t* c = &corners_[size_t{t} * 3];
      if (Contains(t, to)) {
        alive_[t] = 0;
        --live_;
        for (int k = 0; k < 3; ++k) {
          if (c[k] == from) continue;
          std::vector<uint32_t>& list = triangles_of_[c[k]];
          const auto at = std::find(list.begin(), list.end(), t);
          if (at != list.end()) list.erase(at);
        }
      } else {
        for (int k = 0; k < 3; ++k) {
          if (c[k] == from) c[k] = to;
        }
        triangles_of_[to].push_back(t);
      }
    }
    triangles_of_[from].clear();
    gone_[from] = 1;
    quadric_[to].Add(quadric_[from]);
  }

  std::vector<uint32_t> corners_;
  std::vector<Vec> position_;
  std::vector<Quadric> quadric_;
  std::vector<std::vector<uint32_t>> triangles_of_;
  std::vector<uint8_t> locked_, gone_, alive_;
  std::vector<uint32_t> seen_, common_;  // marks of Allowed's current call
  std::vector<uint32_t> neighbours_;
  uint32_t stamp_ = 0, live_ = 0;
};

}  // namespace

std::vector<uint32_t> SimplifiedTriangles(const float* positions, uint32_t vertex_count,
                                          const uint32_t* triangles, uint32_t triangle_count,
                                          double share, double max_error) {
  if (!positions || !triangles || vertex_count == 0 || triangle_count == 0) return {};
  // Each vertex as the first one at its position, bit for bit.
  std::vector<std::array<uint32_t, 3>> key(vertex_count);
  for (uint32_t v = 0; v < vertex_count; ++v) {
    std::memcpy(key[v].data(), positions + size_t{v} * 3, sizeof(key[v]));
  }
  std::vector<uint32_t> order(vertex_count);
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(),
            [&](uint32_t a, uint32_t b) { return key[a] != key[b] ? key[a] < key[b] : a < b; });
  std::vector<uint32_t> first(vertex_count);
  for (size_t i = 0; i < order.size(); ++i) {
    const bool same = i > 0 && key[order[i]] == key[order[i - 1]];
    first[order[i]] = same ? first[order[i - 1]] : order[i];
  }
  std::vector<uint32_t> corners;
  corners.reserve(size_t{triangle_count} * 3);
  Vec low(std::numeric_limits<double>::max()), high(std::numeric_limits<double>::lowest());
  for (uint32_t t = 0; t < triangle_count; ++t) {
    const uint32_t* c = &triangles[size_t{t} * 3];
    if (c[0] >= vertex_count || c[1] >= vertex_count || c[2] >= vertex_count) continue;
    const uint32_t a = first[c[0]], b = first[c[1]], d = first[c[2]];
    if (a == b || b == d || a == d) continue;
    for (uint32_t v : {a, b, d}) {
      const Vec p(positions[size_t{v} * 3], positions[size_t{v} * 3 + 1],
                  positions[size_t{v} * 3 + 2]);
      low = glm::min(low, p);
      high = glm::max(high, p);
    }
    corners.insert(corners.end(), {a, b, d});
  }
  if (corners.empty()) return {};
  const Vec size = high - low;
  const double extent = std::max({size.x, size.y, size.z});
  const double bound = (max_error * extent) * (max_error * extent);
  const uint32_t kept = uint32_t(corners.size() / 3);
  Simplifier s(positions, vertex_count, std::move(corners));
  s.Run(uint32_t(double(kept) * std::clamp(share, 0.0, 1.0)), bound);
  return s.Triangles();
}

std::vector<uint32_t> DepthMapTriangles(const float* positions, uint32_t vertex_count,
                                        const uint32_t* triangles, uint32_t triangle_count) {
  namespace gv = geometric_visibility;
  return SimplifiedTriangles(positions, vertex_count, triangles, triangle_count, gv::kSimplifyShare,
                             gv::kSimplifyError);
}

}  // namespace fvv
