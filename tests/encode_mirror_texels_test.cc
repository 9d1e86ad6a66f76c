// The body's left-right symmetry in the atlas (encoder/encode/mirror_texels.h):
// texels paired across the body model's plane of symmetry, and the texels
// no camera held that take their mirror's colour.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <string>
#include <vector>

#include "encoder/atlas/atlas.h"
#include "encoder/body/generic_body.h"
#include "encoder/body/mesh_ops.h"
#include "encoder/encode/mirror_texels.h"

namespace fvv {
namespace {

struct AtlasOfTheBody {
  Mesh mesh;
  TexelMap map;
  std::vector<Eigen::Vector3f> position;  // per map entry, bind pose
};

AtlasOfTheBody MakeAtlas(uint32_t size) {
  AtlasOfTheBody a;
  const BodyModel body = MakeGenericBody();
  AtlasOptions ao;
  ao.size = size;
  StatusOr<Atlas> atlas = BuildAtlas(body.mesh, ao);
  EXPECT_TRUE(atlas.ok()) << atlas.status().ToString();
  if (!atlas.ok()) return a;
  a.mesh = atlas->mesh;
  a.map = MapAtlasTexels(a.mesh, size);
  const std::vector<Eigen::Vector3f> positions = MeshPositions(a.mesh);
  const std::vector<Eigen::Vector3f> normals = MeshNormals(a.mesh);
  for (size_t e = 0; e < a.map.texel.size(); ++e) {
    Eigen::Vector3f p, n;
    TexelSurfacePoint(a.map, a.mesh.triangles, positions, normals, e, &p, &n);
    a.position.push_back(p);
  }
  return a;
}

// The segment's name with its side exchanged ("l_upper_arm" <-> "r_upper_arm").
std::string OtherSide(const std::string& name) {
  if (name.rfind("l_", 0) == 0) return "r_" + name.substr(2);
  if (name.rfind("r_", 0) == 0) return "l_" + name.substr(2);
  return name;
}

// The segment of the texel map entry's triangle.
std::string SegmentOf(const AtlasOfTheBody& a, size_t entry) {
  return GenericSegmentName(a.mesh.segments[a.mesh.triangles[a.map.triangle[entry]][0]]);
}

bool IsArm(const std::string& segment) {
  return segment.find("arm") != std::string::npos || segment.find("hand") != std::string::npos;
}

TEST(MirrorTexels, PairsEachTexelWithItsTwinOnTheOtherSideOfTheBody) {
  const AtlasOfTheBody a = MakeAtlas(256);
  ASSERT_FALSE(a.map.texel.empty());
  const std::vector<int32_t> mirror = MirrorTexels(a.map, a.mesh);
  ASSERT_EQ(mirror.size(), a.map.texel.size());
  size_t off_plane = 0, paired = 0, returns = 0, same_side = 0, other_segment = 0, arm_to_trunk = 0;
  for (size_t e = 0; e < mirror.size(); ++e) {
    const Eigen::Vector3f& p = a.position[e];
    if (std::abs(p.x()) < 0.02f) {
      EXPECT_EQ(mirror[e], -1) << "a texel on the plane is its own mirror";
      continue;
    }
    ++off_plane;
    if (mirror[e] < 0) continue;
    ++paired;
    const Eigen::Vector3f& q = a.position[size_t(mirror[e])];
    EXPECT_LT((Eigen::Vector3f(-p.x(), p.y(), p.z()) - q).norm(), 0.02f);
    same_side += (p.x() > 0) == (q.x() > 0);
    const std::string own = SegmentOf(a, e), twin = SegmentOf(a, size_t(mirror[e]));
    other_segment += twin != OtherSide(own);
    arm_to_trunk += IsArm(own) != IsArm(twin);
    // The pairing runs both ways: the mirror's mirror lies where the texel does.
    const int32_t back = mirror[size_t(mirror[e])];
    returns += back >= 0 && (a.position[size_t(back)] - p).norm() < 0.01f;
  }
  std::printf(
      "  %zu of %zu texels off the plane paired; %zu return within 1 cm; %zu on "
      "another segment than the twin's, %zu between an arm and the trunk\n",
      paired, off_plane, returns, other_segment, arm_to_trunk);
  // The model is built symmetric: nearly every texel has its twin.
  EXPECT_GT(paired, off_plane * 95 / 100);
  EXPECT_GT(returns, paired * 95 / 100);
  EXPECT_EQ(same_side, 0u);
  // Twins lie on the twin segment, or near a joint on the next one (an
  // elbow's texel on the other forearm); an arm's inner side never pairs
  // with the trunk beside it, which faces another way.
  EXPECT_LT(other_segment, paired / 10);
  EXPECT_EQ(arm_to_trunk, 0u);
}

TEST(MirrorTexels, FillsOnlyDeepInsideWhatNoCameraHeldAndFromASeenTwin) {
  const AtlasOfTheBody a = MakeAtlas(256);
  ASSERT_FALSE(a.map.texel.empty());
  const std::vector<int32_t> mirror = MirrorTexels(a.map, a.mesh);
  const uint32_t size = a.map.size;
  // Cameras that held the body's +x side and saw it, except its lower half.
  std::vector<uint8_t> held(size_t(size) * size, 0), seen(held.size(), 0);
  for (size_t e = 0; e < a.map.texel.size(); ++e) {
    held[a.map.texel[e]] = a.position[e].x() > 0;
    seen[a.map.texel[e]] = a.position[e].x() > 0 && a.position[e].y() > 0.9f;
  }
  const uint32_t gap = MirrorFillGap(size);
  EXPECT_EQ(gap, 3u);
  EXPECT_EQ(MirrorFillGap(512), 6u);
  EXPECT_EQ(MirrorFillGap(16), 1u);
  const auto targets = MirrorFillTargets(a.map, mirror, held, seen, gap);
  ASSERT_GT(targets.size(), 1000u);
  std::vector<uint8_t> target(held.size(), 0);
  for (const auto& [entry, other] : targets) {
    ASSERT_EQ(int32_t(other), mirror[entry]);
    EXPECT_FALSE(held[a.map.texel[entry]]);
    EXPECT_TRUE(seen[a.map.texel[other]]);
    target[a.map.texel[entry]] = 1;
  }
  // Next to what the cameras held, the fill from the texels around is left.
  for (uint32_t texel : a.map.texel) {
    if (held[texel]) continue;
    const uint32_t x = texel % size, y = texel / size;
    const bool beside = (x > 0 && held[texel - 1]) || (x + 1 < size && held[texel + 1]) ||
                        (y > 0 && held[texel - size]) || (y + 1 < size && held[texel + size]);
    if (beside) {
      EXPECT_FALSE(target[texel]) << texel;
    }
  }
  // A wider gap fills fewer, and only texels the narrower one filled.
  const auto fewer = MirrorFillTargets(a.map, mirror, held, seen, 4 * gap);
  EXPECT_LT(fewer.size(), targets.size());
  for (const auto& [entry, other] : fewer) EXPECT_TRUE(target[a.map.texel[entry]]);
  // Nothing to fill where every texel is held, nor from twins nobody saw.
  std::vector<uint8_t> all(held.size(), 1), none(held.size(), 0);
  EXPECT_TRUE(MirrorFillTargets(a.map, mirror, all, all, gap).empty());
  EXPECT_TRUE(MirrorFillTargets(a.map, mirror, held, none, gap).empty());
}

}  // namespace
}  // namespace fvv
