// The generic body model: structure, closed segment meshes, human
// proportions, skinning that keeps bent joints closed; kinematics conventions.
#include <gtest/gtest.h>

#include <map>
#include <random>
#include <set>

#include "container/file_header.h"
#include "encoder/body/generic_body.h"
#include "encoder/body/kinematics.h"

namespace fvv {
namespace {

using Eigen::Vector3d;
using Eigen::Vector3f;

TEST(GenericBody, SkeletonHas17Joints16Segments35Dofs) {
  const BodyModel m = MakeGenericBody();
  EXPECT_EQ(m.skeleton.bones.size(), 17u);
  EXPECT_EQ(m.skeleton.Dofs().size(), 35u);
  std::set<uint8_t> segments(m.mesh.segments.begin(), m.mesh.segments.end());
  EXPECT_EQ(segments.size(), 16u);
  for (const DofRef& d : m.skeleton.Dofs()) {
    const Bone& b = m.skeleton.bones[d.bone];
    EXPECT_LT(b.dof_min[d.kind], b.dof_max[d.kind]) << b.name << " DOF " << int(d.kind);
  }
  EXPECT_GE(m.mesh.triangles.size(), 21000u);
  EXPECT_TRUE(ValidateBodyModel(m, FindLevel(1)).ok());
}

// Every segment is closed and consistently oriented once positions shared
// across chart seams are welded: each directed edge appears exactly once and
// its reverse exactly once; the enclosed volume is positive (normals outward).
TEST(GenericBody, SegmentsAreClosedOutwardMeshes) {
  const BodyModel m = MakeGenericBody();
  for (int s = 0; s < kGenericSegmentCount; ++s) {
    std::map<std::array<float, 3>, uint32_t> weld;
    auto id = [&](uint32_t v) {
      return weld.emplace(m.mesh.positions[v], weld.size()).first->second;
    };
    std::map<std::pair<uint32_t, uint32_t>, int> directed;
    double volume = 0;
    for (const auto& t : m.mesh.triangles) {
      if (m.mesh.segments[t[0]] != s) continue;
      const uint32_t a = id(t[0]), b = id(t[1]), c = id(t[2]);
      ASSERT_TRUE(a != b && b != c && a != c) << GenericSegmentName(s) << ": degenerate triangle";
      ++directed[{a, b}], ++directed[{b, c}], ++directed[{c, a}];
      const auto& p = m.mesh.positions;
      const Vector3d p0(p[t[0]][0], p[t[0]][1], p[t[0]][2]), p1(p[t[1]][0], p[t[1]][1], p[t[1]][2]),
          p2(p[t[2]][0], p[t[2]][1], p[t[2]][2]);
      volume += p0.dot(p1.cross(p2)) / 6;
    }
    ASSERT_FALSE(directed.empty());
    for (const auto& [edge, count] : directed) {
      ASSERT_EQ(count, 1) << GenericSegmentName(s) << ": edge used twice in one direction";
      ASSERT_EQ(directed.count({edge.second, edge.first}), 1u)
          << GenericSegmentName(s) << ": open edge";
    }
    EXPECT_GT(volume, 0) << GenericSegmentName(s);
  }
}

TEST(GenericBody, HumanProportionsAndShapeScales) {
  auto extent = [](const BodyModel& m, int axis) {
    float lo = 1e9f, hi = -1e9f;
    for (const auto& p : m.mesh.positions) lo = std::min(lo, p[axis]), hi = std::max(hi, p[axis]);
    return std::make_pair(lo, hi);
  };
  const BodyModel m = MakeGenericBody();
  const auto [ylo, yhi] = extent(m, 1);
  EXPECT_NEAR(ylo, 0.0, 0.01);  // feet on the floor
  EXPECT_NEAR(yhi - ylo, 1.75, 0.03);
  const auto [xlo, xhi] = extent(m, 0);  // T-pose arm span is about the stature
  EXPECT_NEAR(xhi - xlo, 1.8, 0.1);
  BodyShape tall;
  tall.stature = 1.1;
  const auto [tlo, thi] = extent(MakeGenericBody(tall), 1);
  EXPECT_NEAR((thi - tlo) / (yhi - ylo), 1.1, 0.01);
  BodyShape heavy;
  heavy.girth[kSegAbdomen] = 1.4;
  const BodyModel h = MakeGenericBody(heavy);
  float wide = 0, slim = 0;
  for (size_t v = 0; v < h.mesh.positions.size(); ++v) {
    if (h.mesh.segments[v] != kSegAbdomen) continue;
    wide = std::max(wide, h.mesh.positions[v][0]);
    slim = std::max(slim, m.mesh.positions[v][0]);
  }
  EXPECT_NEAR(wide / slim, 1.4, 0.02);
  heavy.girth[kSegAbdomen] = 3;
  EXPECT_FALSE(ValidateBodyShape(heavy).ok());
  // The head's range is wider (cartoon characters), up to kMaxHeadScale only.
  BodyShape cartoon;
  cartoon.girth[kSegHead] = 2.8;
  cartoon.length[kSegHead] = 2.2;
  EXPECT_TRUE(ValidateBodyShape(cartoon).ok());
  cartoon.girth[kSegHead] = kMaxHeadScale + 0.1;
  const Status too_wide = ValidateBodyShape(cartoon);
  EXPECT_FALSE(too_wide.ok());
  EXPECT_NE(too_wide.message().find("head"), std::string::npos) << too_wide.message();
  EXPECT_NE(too_wide.message().find("[0.5, 3]"), std::string::npos) << too_wide.message();
  cartoon.girth[kSegHead] = 1;
  cartoon.girth[kSegChest] = 2.2;  // other segments keep [0.5, 2]
  EXPECT_FALSE(ValidateBodyShape(cartoon).ok());
  cartoon.girth[kSegChest] = 1;
  for (double bad : {0.2, 1.1, std::nan("")}) {
    cartoon.neck_ratio = bad;
    const Status neck = ValidateBodyShape(cartoon);
    EXPECT_FALSE(neck.ok()) << bad;
    EXPECT_NE(neck.message().find("neck ratio"), std::string::npos) << neck.message();
  }
}

// A large head on a thin neck: the neck ratio narrows the head segment's
// lower part (the neck, at the head's girth times the ratio) and leaves the
// skull's girth and the rest of the body as they were.
TEST(BodyShape, NeckRatioNarrowsTheNeckOnly) {
  BodyShape big_head;
  big_head.girth[kSegHead] = 2.5;
  BodyShape thin_neck = big_head;
  thin_neck.neck_ratio = 0.4;
  ASSERT_TRUE(ValidateBodyShape(thin_neck).ok());
  const BodyModel a = MakeGenericBody(big_head), b = MakeGenericBody(thin_neck);
  ASSERT_EQ(a.mesh.positions.size(), b.mesh.positions.size());
  // Half-widths (across X, the head's width axis) below the neck joint + 3 cm
  // (the neck) and 13 cm above it (the skull).
  const Eigen::Vector3f neck = JointPositions(a.skeleton, {})[kNeck].cast<float>();
  double neck_a = 0, neck_b = 0, skull_a = 0, skull_b = 0;
  int others_moved = 0;
  for (size_t v = 0; v < a.mesh.positions.size(); ++v) {
    const auto& pa = a.mesh.positions[v];
    const auto& pb = b.mesh.positions[v];
    if (a.mesh.segments[v] != kSegHead) {
      others_moved += pa != pb;
      continue;
    }
    const double ra = std::abs(pa[0] - neck.x()), rb = std::abs(pb[0] - neck.x());
    if (pa[1] < neck.y() + 0.03) neck_a = std::max(neck_a, ra), neck_b = std::max(neck_b, rb);
    if (pa[1] > neck.y() + 0.13) skull_a = std::max(skull_a, ra), skull_b = std::max(skull_b, rb);
  }
  EXPECT_EQ(others_moved, 0);
  EXPECT_NEAR(neck_b / neck_a, 0.4, 0.03);
  EXPECT_NEAR(skull_b / skull_a, 1.0, 1e-6);
}

// Ray-parity inside test against one segment's posed triangles.
bool InsideSegment(const Mesh& mesh, const std::vector<Vector3f>& posed, int segment,
                   const Vector3d& q) {
  const Vector3d dir = Vector3d(0.31, 0.83, 0.47).normalized();  // generic direction
  int hits = 0;
  for (const auto& t : mesh.triangles) {
    if (mesh.segments[t[0]] != segment) continue;
    const Vector3d a = posed[t[0]].cast<double>(), b = posed[t[1]].cast<double>(),
                   c = posed[t[2]].cast<double>();
    const Vector3d e1 = b - a, e2 = c - a, p = dir.cross(e2);
    const double det = e1.dot(p);
    if (std::abs(det) < 1e-14) continue;
    const Vector3d s = q - a;
    const double u = s.dot(p) / det;
    if (u < 0 || u > 1) continue;
    const Vector3d qv = s.cross(e1);
    const double v = dir.dot(qv) / det;
    if (v < 0 || u + v > 1) continue;
    if (e2.dot(qv) / det > 0) ++hits;
  }
  return hits % 2 == 1;
}

// Bent knees, elbows and hips: points around each bent joint stay inside the
// skinned body (a tear or gap at the joint would expose them).
TEST(GenericBody, BentJointsStayClosed) {
  const BodyModel m = MakeGenericBody();
  const std::vector<DofRef> refs = m.skeleton.Dofs();
  std::vector<double> pose(refs.size(), 0.0);
  auto set = [&](int bone, int kind, double v) {
    for (size_t d = 0; d < refs.size(); ++d) {
      if (refs[d].bone == bone && refs[d].kind == kind) pose[d] = v;
    }
  };
  set(kLeftKnee, 0, 1.6);
  set(kRightKnee, 0, 0.9);
  set(kLeftElbow, 1, -1.8);
  set(kRightElbow, 1, 1.2);
  set(kLeftHip, 0, -1.2);
  set(kLeftShoulder, 2, -1.3);
  set(kLumbar, 0, 0.6);
  const std::vector<Vector3f> posed = SkinPositions(m.mesh, SkinningMatrices(m.skeleton, pose));
  const std::vector<Vector3d> joints = JointPositions(m.skeleton, pose);
  for (int j : {kLeftKnee, kRightKnee, kLeftElbow, kRightElbow, kLeftHip, kLeftShoulder, kLumbar}) {
    const double r = j == kLeftElbow || j == kRightElbow ? 0.022 : 0.03;
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dz = -1; dz <= 1; ++dz) {
          const Vector3d q = joints[j] + r * Vector3d(dx, dy, dz).normalized().eval() *
                                             (dx || dy || dz ? 1.0 : 0.0);
          bool inside = false;
          for (int s = 0; s < kGenericSegmentCount && !inside; ++s) {
            inside = InsideSegment(m.mesh, posed, s, q);
          }
          EXPECT_TRUE(inside) << GenericJointName(j) << " offset " << dx << dy << dz;
        }
      }
    }
  }
}

TEST(GenericBody, SkinWeightsVarySmoothly) {
  const BodyModel m = MakeGenericBody();
  for (size_t v = 0; v < m.mesh.positions.size(); ++v) {
    uint32_t sum = 0;
    for (int k = 0; k < kMaxInfluences; ++k) sum += m.mesh.weights[v][k];
    ASSERT_EQ(sum, 65535u);
  }
  // Along each ring edge of the mesh, no bone's weight jumps by more than 0.5.
  for (const auto& t : m.mesh.triangles) {
    for (int e = 0; e < 3; ++e) {
      const uint32_t a = t[e], b = t[(e + 1) % 3];
      std::map<int, double> wa, wb;
      for (int k = 0; k < kMaxInfluences; ++k) {
        wa[m.mesh.joints[a][k]] += m.mesh.weights[a][k] / 65535.0;
        wb[m.mesh.joints[b][k]] += m.mesh.weights[b][k] / 65535.0;
      }
      for (const auto& [bone, w] : wa) {
        ASSERT_LT(std::abs(w - wb[bone]), 0.5)
            << "bone " << bone << " segment " << GenericSegmentName(m.mesh.segments[a]) << " y "
            << m.mesh.positions[a][1] << " " << m.mesh.positions[b][1];
      }
    }
  }
}

TEST(Kinematics, EulerRoundTripAllOrders) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.4, 1.4);
  for (int o = 0; o < kRotationOrderCount; ++o) {
    for (int i = 0; i < 50; ++i) {
      const Vector3d a(u(rng), u(rng), u(rng));
      const Eigen::Matrix3d r = EulerMatrix(RotationOrder(o), a);
      const Vector3d back = MatrixToEuler(RotationOrder(o), r);
      EXPECT_LT((EulerMatrix(RotationOrder(o), back) - r).norm(), 1e-9) << "order " << o;
      EXPECT_LT((back - a).norm(), 1e-9) << "order " << o;
    }
  }
}

TEST(Kinematics, RestPoseSkinsToBindPose) {
  const BodyModel m = MakeGenericBody();
  const std::vector<Vector3f> p = SkinPositions(m.mesh, SkinningMatrices(m.skeleton, {}));
  for (size_t v = 0; v < p.size(); v += 97) {
    EXPECT_NEAR(p[v].x(), m.mesh.positions[v][0], 1e-5);
    EXPECT_NEAR(p[v].y(), m.mesh.positions[v][1], 1e-5);
  }
  // Translating the root moves every vertex by the same amount.
  std::vector<double> pose(35, 0.0);
  pose[0] = 0.5;  // root translation X is the first DOF listed? Find it.
  const std::vector<DofRef> refs = m.skeleton.Dofs();
  std::fill(pose.begin(), pose.end(), 0.0);
  for (size_t d = 0; d < refs.size(); ++d) {
    if (refs[d].bone == kRoot && refs[d].kind == 3) pose[d] = 0.5;
  }
  const std::vector<Vector3f> moved = SkinPositions(m.mesh, SkinningMatrices(m.skeleton, pose));
  for (size_t v = 0; v < p.size(); v += 101) EXPECT_NEAR(moved[v].x() - p[v].x(), 0.5, 1e-5);
}

}  // namespace
}  // namespace fvv
