// The simplified body the players' camera depth maps draw
// (player/playback/depth_map_triangles.h): a quarter of the triangles, the
// same closed surface within millimetres, wound as the model, over its own
// vertices, and the same triangles on every call.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <utility>
#include <vector>

#include "container/geometric_visibility.h"
#include "encoder/body/generic_body.h"
#include "player/playback/depth_map_triangles.h"

namespace fvv {
namespace {

using P = std::array<double, 3>;

P At(const std::vector<float>& positions, uint32_t v) {
  return {positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]};
}
P Minus(const P& a, const P& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double Dot(const P& a, const P& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
P Cross(const P& a, const P& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

// Distance from p to triangle abc (closest point by the triangle's regions).
double PointTriangle(const P& p, const P& a, const P& b, const P& c) {
  const P ab = Minus(b, a), ac = Minus(c, a), ap = Minus(p, a);
  const auto distance_to = [&](double s, double t) {
    double r = 0;
    for (int k = 0; k < 3; ++k) {
      const double x = a[k] + s * ab[k] + t * ac[k] - p[k];
      r += x * x;
    }
    return std::sqrt(r);
  };
  const double d1 = Dot(ab, ap), d2 = Dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return distance_to(0, 0);
  const P bp = Minus(p, b);
  const double d3 = Dot(ab, bp), d4 = Dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return distance_to(1, 0);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return distance_to(d1 / (d1 - d3), 0);
  const P cp = Minus(p, c);
  const double d5 = Dot(ab, cp), d6 = Dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return distance_to(0, 1);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return distance_to(0, d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return distance_to(1 - w, w);
  }
  const double scale = 1 / (va + vb + vc);
  return distance_to(vb * scale, vc * scale);
}

// The farthest any of every `step`-th vertex lies from the triangles.
double FarthestVertex(const std::vector<float>& positions, const std::vector<uint32_t>& triangles,
                      uint32_t step) {
  double farthest = 0;
  for (uint32_t v = 0; v < positions.size() / 3; v += step) {
    double nearest = 1e9;
    for (size_t t = 0; t < triangles.size(); t += 3) {
      nearest = std::min(
          nearest, PointTriangle(At(positions, v), At(positions, triangles[t]),
                                 At(positions, triangles[t + 1]), At(positions, triangles[t + 2])));
    }
    farthest = std::max(farthest, nearest);
  }
  return farthest;
}

// How many times each edge (by position, so seams' twins are one) is used.
std::map<std::pair<P, P>, int> EdgeUses(const std::vector<float>& positions,
                                        const std::vector<uint32_t>& triangles) {
  std::map<std::pair<P, P>, int> uses;
  for (size_t t = 0; t < triangles.size(); t += 3) {
    for (int k = 0; k < 3; ++k) {
      const P a = At(positions, triangles[t + k]), b = At(positions, triangles[t + (k + 1) % 3]);
      ++uses[std::minmax(a, b)];
    }
  }
  return uses;
}

struct Surface {
  std::vector<float> positions;
  std::vector<uint32_t> triangles;
};

Surface GenericBody() {
  const BodyModel body = MakeGenericBody();
  Surface s;
  for (const auto& p : body.mesh.positions)
    s.positions.insert(s.positions.end(), p.begin(), p.end());
  for (const auto& t : body.mesh.triangles)
    s.triangles.insert(s.triangles.end(), t.begin(), t.end());
  return s;
}

// A sphere of radius 0.3 m as a latitude-longitude grid: the column at
// longitude 2 pi repeats the one at 0 and each pole is one vertex per column
// (a texture's seams, as the body model has them), wound outward.
Surface Sphere(int columns, int rows) {
  Surface s;
  for (int r = 0; r <= rows; ++r) {
    for (int c = 0; c <= columns; ++c) {
      const double theta = M_PI * r / rows, phi = 2 * M_PI * (c % columns) / columns;
      const double ring = r == 0 || r == rows ? 0.0 : std::sin(theta);
      s.positions.insert(s.positions.end(),
                         {float(0.3 * ring * std::cos(phi)), float(0.3 * std::cos(theta)),
                          float(0.3 * ring * std::sin(phi))});
    }
  }
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < columns; ++c) {
      const uint32_t a = r * (columns + 1) + c, b = a + 1, d = a + columns + 1, e = d + 1;
      if (r != 0) s.triangles.insert(s.triangles.end(), {a, b, d});
      if (r != rows - 1) s.triangles.insert(s.triangles.end(), {b, e, d});
    }
  }
  return s;
}

std::vector<uint32_t> Simplify(const Surface& s) {
  return DepthMapTriangles(s.positions.data(), uint32_t(s.positions.size() / 3), s.triangles.data(),
                           uint32_t(s.triangles.size() / 3));
}

TEST(DepthMapTriangles, TheBodyInAQuarterOfItsTrianglesWithinMillimetres) {
  const Surface body = GenericBody();
  const std::vector<uint32_t> kept = Simplify(body);
  const size_t model = body.triangles.size() / 3, simplified = kept.size() / 3;
  const double farthest = FarthestVertex(body.positions, kept, 5);
  std::printf("  %zu of %zu triangles; every 5th model vertex within %.2f mm\n", simplified, model,
              1000 * farthest);
  EXPECT_LE(simplified, size_t(geometric_visibility::kSimplifyShare * model) + 1);
  EXPECT_GT(simplified, model / 8);  // the error bound stops it well before
  EXPECT_LT(farthest, 0.004);        // a fifth of the depth test's tolerance
  for (uint32_t i : kept) ASSERT_LT(i, body.positions.size() / 3);
  // Closed as the model is (seams joined by position): no hole the depth
  // maps could see through, no edge shared by three triangles.
  for (const auto& [edge, uses] : EdgeUses(body.positions, kept)) ASSERT_EQ(uses, 2);
  EXPECT_EQ(kept, Simplify(body));  // the same triangles every time
}

TEST(DepthMapTriangles, ASphereStaysRoundAndFacesOutward) {
  const Surface sphere = Sphere(96, 64);
  const std::vector<uint32_t> kept = Simplify(sphere);
  ASSERT_FALSE(kept.empty());
  EXPECT_LE(kept.size(), sphere.triangles.size() / 4 + 3);
  for (const auto& [edge, uses] : EdgeUses(sphere.positions, kept)) ASSERT_EQ(uses, 2);
  for (size_t t = 0; t < kept.size(); t += 3) {
    const P a = At(sphere.positions, kept[t]), b = At(sphere.positions, kept[t + 1]),
            c = At(sphere.positions, kept[t + 2]);
    const P centroid = {(a[0] + b[0] + c[0]) / 3, (a[1] + b[1] + c[1]) / 3,
                        (a[2] + b[2] + c[2]) / 3};
    ASSERT_GT(Dot(Cross(Minus(b, a), Minus(c, a)), centroid), 0) << "triangle " << t / 3;
    // Its centre no deeper inside than the bound allows (0.2 % of 0.6 m,
    // root mean square, so a little more at worst).
    EXPECT_GT(std::sqrt(Dot(centroid, centroid)), 0.3 - 0.004) << "triangle " << t / 3;
  }
}

TEST(DepthMapTriangles, AnOpenBorderStaysWhereItIs) {
  // A flat 20 x 20 grid: its border edges are used once before and after, and
  // the plane itself simplifies for free.
  Surface grid;
  const int n = 20;
  for (int y = 0; y <= n; ++y) {
    for (int x = 0; x <= n; ++x)
      grid.positions.insert(grid.positions.end(), {x * 0.01f, y * 0.01f, 0});
  }
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      const uint32_t a = y * (n + 1) + x, b = a + 1, c = a + n + 1, d = c + 1;
      grid.triangles.insert(grid.triangles.end(), {a, b, c, b, d, c});
    }
  }
  const std::vector<uint32_t> kept = Simplify(grid);
  EXPECT_LT(kept.size(), grid.triangles.size() / 3);
  const auto before = EdgeUses(grid.positions, grid.triangles);
  size_t border = 0;
  for (const auto& [edge, uses] : before) border += uses == 1;
  size_t border_after = 0;
  for (const auto& [edge, uses] : EdgeUses(grid.positions, kept)) {
    ASSERT_LE(uses, 2);
    if (uses == 1) {
      ++border_after;
      EXPECT_EQ(before.count(edge), 1u);  // an edge of the original border
    }
  }
  EXPECT_EQ(border_after, border);
}

// Pushed far past any useful bound, it still refuses what would break the
// surface: a sphere ends as a small closed solid wound outward (never two
// triangles back to back, never an edge of three), a plane never folds
// (every triangle still faces up, covering the grid's area once).
TEST(DepthMapTriangles, NoCollapseFoldsOrPinchesTheSurface) {
  const Surface sphere = Sphere(24, 16);
  const std::vector<uint32_t> solid = SimplifiedTriangles(
      sphere.positions.data(), uint32_t(sphere.positions.size() / 3), sphere.triangles.data(),
      uint32_t(sphere.triangles.size() / 3), 0.0, 10.0);
  EXPECT_GE(solid.size(), 12u);  // a tetrahedron at the least
  for (const auto& [edge, uses] : EdgeUses(sphere.positions, solid)) ASSERT_EQ(uses, 2);
  double volume = 0;  // signed: positive when wound outward
  for (size_t t = 0; t < solid.size(); t += 3) {
    volume += Dot(At(sphere.positions, solid[t]),
                  Cross(At(sphere.positions, solid[t + 1]), At(sphere.positions, solid[t + 2]))) /
              6;
  }
  EXPECT_GT(volume, 0.0);

  Surface grid;
  const int n = 16;
  for (int y = 0; y <= n; ++y) {
    for (int x = 0; x <= n; ++x) {
      // Jittered inside, so that collapses have non-convex rings to fold over.
      const bool inside = x > 0 && x < n && y > 0 && y < n;
      const float jx = inside ? 0.004f * float((x * 7 + y * 3) % 5 - 2) : 0.0f;
      const float jy = inside ? 0.004f * float((x * 5 + y * 11) % 5 - 2) : 0.0f;
      grid.positions.insert(grid.positions.end(), {x * 0.01f + jx, y * 0.01f + jy, 0});
    }
  }
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      const uint32_t a = y * (n + 1) + x, b = a + 1, c = a + n + 1, d = c + 1;
      grid.triangles.insert(grid.triangles.end(), {a, b, c, b, d, c});
    }
  }
  const std::vector<uint32_t> flat =
      SimplifiedTriangles(grid.positions.data(), uint32_t(grid.positions.size() / 3),
                          grid.triangles.data(), uint32_t(grid.triangles.size() / 3), 0.0, 10.0);
  ASSERT_LT(flat.size(), grid.triangles.size() / 4);
  double area = 0;
  for (size_t t = 0; t < flat.size(); t += 3) {
    const P a = At(grid.positions, flat[t]), b = At(grid.positions, flat[t + 1]),
            c = At(grid.positions, flat[t + 2]);
    const double up = Cross(Minus(b, a), Minus(c, a))[2];
    ASSERT_GT(up, 0) << "triangle " << t / 3 << " turned over";
    area += up / 2;
  }
  EXPECT_NEAR(area, (n * 0.01) * (n * 0.01), 1e-6);
}

TEST(DepthMapTriangles, LeavesOutWhatIsNoTriangle) {
  EXPECT_TRUE(DepthMapTriangles(nullptr, 0, nullptr, 0).empty());
  const std::vector<float> positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0};
  // One real triangle, one with an index past the vertices, and one whose
  // corners 0 and 3 share a position.
  const std::vector<uint32_t> triangles = {0, 1, 2, 0, 1, 9, 0, 3, 1};
  const std::vector<uint32_t> kept = DepthMapTriangles(positions.data(), 4, triangles.data(), 3);
  EXPECT_EQ(kept, (std::vector<uint32_t>{0, 1, 2}));  // a lone triangle is all border
}

}  // namespace
}  // namespace fvv
