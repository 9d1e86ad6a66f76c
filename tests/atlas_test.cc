// The texture atlas: every triangle of the generic body gets texels,
// none shared with another triangle (rasterised coverage), charts keep their
// gutters, texel density is uniform, seams duplicate vertices faithfully.
#include "encoder/atlas/atlas.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "encoder/body/generic_body.h"

namespace fvv {
namespace {

double UvArea(const Mesh& m, const std::array<uint32_t, 3>& t) {
  const auto& a = m.uvs[t[0]];
  const auto& b = m.uvs[t[1]];
  const auto& c = m.uvs[t[2]];
  return 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
}

double Area3d(const Mesh& m, const std::array<uint32_t, 3>& t) {
  Eigen::Vector3d p[3];
  for (int k = 0; k < 3; ++k)
    p[k] = {m.positions[t[k]][0], m.positions[t[k]][1], m.positions[t[k]][2]};
  return 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).norm();
}

class AtlasTest : public ::testing::TestWithParam<uint32_t> {};

TEST_P(AtlasTest, CoversEveryTriangleWithoutOverlap) {
  const BodyModel body = MakeGenericBody();
  AtlasOptions o;
  o.size = GetParam();
  StatusOr<Atlas> atlas = BuildAtlas(body.mesh, o);
  ASSERT_TRUE(atlas.ok()) << atlas.status().ToString();
  const Mesh& m = atlas->mesh;
  ASSERT_EQ(m.triangles.size(), body.mesh.triangles.size());
  ASSERT_EQ(m.positions.size(), atlas->source_vertex.size());
  for (size_t v = 0; v < m.positions.size(); ++v) {
    ASSERT_EQ(m.positions[v], body.mesh.positions[atlas->source_vertex[v]]);
    ASSERT_EQ(m.joints[v], body.mesh.joints[atlas->source_vertex[v]]);
    ASSERT_TRUE(m.uvs[v][0] > 0 && m.uvs[v][0] < 1 && m.uvs[v][1] > 0 && m.uvs[v][1] < 1);
  }
  // Rasterised coverage at the atlas resolution: each texel centre strictly
  // inside at most one triangle; no triangle folded over (orientation kept).
  const int n = int(o.size);
  std::vector<int> owner(size_t(n) * n, -1);
  size_t covered = 0, overlaps = 0;
  double uv_total = 0;
  for (size_t t = 0; t < m.triangles.size(); ++t) {
    const auto& tri = m.triangles[t];
    const double area = UvArea(m, tri);
    ASSERT_GT(area, 0) << "triangle " << t << " flipped or degenerate in the atlas";
    uv_total += area;
    Eigen::Vector2d p[3];
    for (int k = 0; k < 3; ++k) p[k] = {m.uvs[tri[k]][0] * n, m.uvs[tri[k]][1] * n};
    const int x0 = std::max(0, int(std::floor(std::min({p[0].x(), p[1].x(), p[2].x()}))));
    const int x1 = std::min(n - 1, int(std::ceil(std::max({p[0].x(), p[1].x(), p[2].x()}))));
    const int y0 = std::max(0, int(std::floor(std::min({p[0].y(), p[1].y(), p[2].y()}))));
    const int y1 = std::min(n - 1, int(std::ceil(std::max({p[0].y(), p[1].y(), p[2].y()}))));
    const double twice = 2 * area * n * n;
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const Eigen::Vector2d q(x + 0.5, y + 0.5);
        double b[3];
        for (int k = 0; k < 3; ++k) {
          const Eigen::Vector2d& a = p[(k + 1) % 3];
          const Eigen::Vector2d& c = p[(k + 2) % 3];
          b[k] = ((c - a).x() * (q - a).y() - (c - a).y() * (q - a).x()) / twice;
        }
        if (b[0] <= 1e-9 || b[1] <= 1e-9 || b[2] <= 1e-9) continue;
        int& o_t = owner[size_t(y) * n + x];
        if (o_t >= 0)
          ++overlaps;
        else
          ++covered, o_t = int(t);
      }
    }
  }
  EXPECT_EQ(overlaps, 0u);
  // The charts use a fair share of the atlas (packing, not waste).
  std::printf("  %u: %zu charts, %.0f texels/m, %.1f %% of texels covered\n", o.size,
              atlas->charts.size(), atlas->texels_per_metre, 100.0 * covered / (double(n) * n));
  EXPECT_GT(uv_total, 0.35);
  // Charts stay inside the atlas and apart, and their UVs inside their own
  // rectangle minus the gutter.
  for (size_t i = 0; i < atlas->charts.size(); ++i) {
    const AtlasChart& a = atlas->charts[i];
    ASSERT_LE(a.x + a.width, o.size);
    ASSERT_LE(a.y + a.height, o.size);
    for (uint32_t t : a.triangles) {
      for (uint32_t v : m.triangles[t]) {
        const double u = m.uvs[v][0] * n, w = m.uvs[v][1] * n;
        ASSERT_GE(u, a.x + o.gutter - 1e-6);
        ASSERT_LE(u, a.x + a.width - o.gutter + 1e-6);
        ASSERT_GE(w, a.y + o.gutter - 1e-6);
        ASSERT_LE(w, a.y + a.height - o.gutter + 1e-6);
      }
    }
    for (size_t j = i + 1; j < atlas->charts.size(); ++j) {
      const AtlasChart& b = atlas->charts[j];
      const bool apart = a.x + a.width <= b.x || b.x + b.width <= a.x || a.y + a.height <= b.y ||
                         b.y + b.height <= a.y;
      ASSERT_TRUE(apart) << "charts " << i << " and " << j << " overlap";
    }
  }
  // One density for the whole body: per chart, texel area over surface area
  // lies between cos(deviation) (projection foreshortening) and 1 of the target.
  const double target = atlas->texels_per_metre * atlas->texels_per_metre;
  for (const AtlasChart& a : atlas->charts) {
    double uv = 0, surface = 0;
    for (uint32_t t : a.triangles)
      uv += UvArea(m, m.triangles[t]) * n * n, surface += Area3d(m, m.triangles[t]);
    if (surface < 1e-6) continue;
    const double ratio = uv / surface / target;
    EXPECT_GT(ratio, 0.5);
    EXPECT_LT(ratio, 1.001);  // float UVs
  }
}

INSTANTIATE_TEST_SUITE_P(Sizes, AtlasTest, ::testing::Values(256u, 512u, 1024u));

TEST(Atlas, RejectsBadOptions) {
  const BodyModel body = MakeGenericBody();
  AtlasOptions o;
  o.size = 8;
  EXPECT_FALSE(BuildAtlas(body.mesh, o).ok());
  o.size = 512;
  o.max_normal_deviation = 95;
  EXPECT_FALSE(BuildAtlas(body.mesh, o).ok());
  o.max_normal_deviation = 50;
  o.size = 16;
  o.gutter = 4;  // hundreds of charts cannot fit 16x16 with 4-texel gutters
  EXPECT_FALSE(BuildAtlas(body.mesh, o).ok());
  EXPECT_FALSE(BuildAtlas(Mesh(), AtlasOptions()).ok());
}

}  // namespace
}  // namespace fvv
