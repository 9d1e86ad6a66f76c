// Importers: BVH motion and its retargeting onto the generic body
// model; skinned, animated glTF 2.0 characters (CesiumMan from ../shared/data).
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "encoder/body/generic_body.h"
#include "encoder/body/kinematics.h"
#include "encoder/import/bvh.h"
#include "encoder/import/gltf.h"
#include "encoder/import/retarget.h"

namespace fvv {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180;

// A CMU-named skeleton in the generic model's rest pose (legs straight down,
// arms along +-X), centimetres, two frames: rest, then bent.
std::string TestBvh(const std::string& second_frame_override = "") {
  std::ostringstream s;
  auto joint = [&](const char* kind, const char* name, double x, double y, double z, bool end,
                   double ex = 0, double ey = 0, double ez = 0) {
    s << kind << " " << name << "\n{\nOFFSET " << x << " " << y << " " << z << "\nCHANNELS "
      << (std::string(kind) == "ROOT" ? "6 Xposition Yposition Zposition " : "3 ")
      << "Zrotation Yrotation Xrotation\n";
    if (end) s << "End Site\n{\nOFFSET " << ex << " " << ey << " " << ez << "\n}\n";
  };
  s << "HIERARCHY\n";
  joint("ROOT", "Hips", 0, 0, 0, false);
  joint("JOINT", "Spine", 0, 10, 0, false);
  joint("JOINT", "Spine1", 0, 19, 0, false);
  joint("JOINT", "Neck", 0, 23, 0, false);
  joint("JOINT", "Head", 0, 10, 0, true, 0, 18, 0);
  s << "}\n}\n";  // Head, Neck
  for (int side : {1, -1}) {
    joint("JOINT", side > 0 ? "LeftArm" : "RightArm", side * 18, 19, 0, false);
    joint("JOINT", side > 0 ? "LeftForeArm" : "RightForeArm", side * 29, 0, 0, false);
    joint("JOINT", side > 0 ? "LeftHand" : "RightHand", side * 25, 0, 0, true, side * 18, 0, 0);
    s << "}\n}\n}\n";
  }
  s << "}\n}\n";  // Spine1, Spine
  for (int side : {1, -1}) {
    joint("JOINT", side > 0 ? "LeftUpLeg" : "RightUpLeg", side * 9, -5, 0, false);
    joint("JOINT", side > 0 ? "LeftLeg" : "RightLeg", 0, -42, 0, false);
    joint("JOINT", side > 0 ? "LeftFoot" : "RightFoot", 0, -39.5, 0, true, 0, -4, 18);
    s << "}\n}\n}\n";
  }
  s << "}\nMOTION\nFrames: 2\nFrame Time: 0.04\n";
  // 6 root + 3 per joint (16 joints): rest, then the override (or rest again).
  const int values = 6 + 3 * 16;
  for (int f = 0; f < 2; ++f) {
    if (f == 1 && !second_frame_override.empty()) {
      s << second_frame_override << "\n";
      continue;
    }
    s << "0 95 0";
    for (int v = 3; v < values; ++v) s << " 0";
    s << "\n";
  }
  return s.str();
}

// Channel order in TestBvh: Hips(6), Spine, Spine1, Neck, Head, LeftArm,
// LeftForeArm, LeftHand, RightArm, RightForeArm, RightHand, LeftUpLeg, LeftLeg,
// LeftFoot, RightUpLeg, RightLeg, RightFoot (3 each: Z Y X).
std::string Frame(std::vector<std::pair<int, std::array<double, 3>>> zyx) {
  std::vector<double> v(6 + 3 * 16, 0.0);
  v[1] = 95;
  for (const auto& [joint, angles] : zyx) {
    for (int k = 0; k < 3; ++k) v[6 + 3 * joint + k] = angles[k];
  }
  std::ostringstream s;
  for (double x : v) s << x << " ";
  return s.str();
}

TEST(Retarget, TransfersJointAnglesOnAMatchingSkeleton) {
  // Left knee bent 60 degrees, left arm lowered 80 degrees, spine bent 20 degrees.
  const std::string text = TestBvh(Frame({{11, {0, 0, 60}}, {4, {-80, 0, 0}}, {0, {0, 0, 20}}}));
  StatusOr<BvhMotion> bvh = ParseBvh(text, 0.01);
  ASSERT_TRUE(bvh.ok()) << bvh.status().ToString();
  const BodyModel body = MakeGenericBody();
  RetargetOptions o;
  o.fps = 25;
  o.centre = false;
  StatusOr<std::vector<std::vector<double>>> poses = RetargetToGenericBody(*bvh, body.skeleton, o);
  ASSERT_TRUE(poses.ok()) << poses.status().ToString();
  ASSERT_EQ(poses->size(), 2u);
  const auto& p = (*poses)[1];
  EXPECT_NEAR(p[DofIndex(body.skeleton, kLeftKnee, 0)], 60 * kDeg, 1e-6);
  EXPECT_NEAR(p[DofIndex(body.skeleton, kLeftShoulder, 2)], -80 * kDeg, 1e-6);
  EXPECT_NEAR(p[DofIndex(body.skeleton, kLumbar, 0)], 20 * kDeg, 1e-6);
  EXPECT_NEAR(p[DofIndex(body.skeleton, kRightKnee, 0)], 0.0, 1e-9);
  // Standing at rest: ankles at their rest height (feet on the floor).
  const std::vector<Eigen::Vector3d> rest = JointPositions(body.skeleton, {});
  const std::vector<Eigen::Vector3d> j0 = JointPositions(body.skeleton, (*poses)[0]);
  EXPECT_NEAR(j0[kLeftAnkle].y(), rest[kLeftAnkle].y(), 1e-6);
}

TEST(Retarget, NamesMissingJointsAndShortClips) {
  std::string text = TestBvh();
  text.replace(text.find("LeftLeg"), 7, "LeftBit");
  StatusOr<BvhMotion> bvh = ParseBvh(text, 0.01);
  ASSERT_TRUE(bvh.ok());
  const BodyModel body = MakeGenericBody();
  RetargetOptions o;
  StatusOr<std::vector<std::vector<double>>> r = RetargetToGenericBody(*bvh, body.skeleton, o);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("l_knee"), std::string::npos) << r.status().message();
  bvh = ParseBvh(TestBvh(), 0.01);
  o.frames = 50;  // the clip holds two frames
  r = RetargetToGenericBody(*bvh, body.skeleton, o);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("frames"), std::string::npos);
}

// The CMU clips in Debian's assimp-testmodels load, and their limbs' directions
// carry over to the generic body: hinge planes are chosen so that even the
// one-DOF elbows and knees reproduce the mocap limb directions.
TEST(Retarget, CmuClipLimbDirectionsCarryOver) {
  const std::string path = "/usr/share/assimp/models/BVH/01_01.bvh";
  struct stat st;
  if (stat(path.c_str(), &st) != 0)
    GTEST_SKIP() << path << " absent (apt-get install assimp-testmodels)";
  for (const char* file : {"01_01.bvh", "01_03.bvh", "Boxing_Toes.bvh"}) {
    StatusOr<BvhMotion> m = ReadBvhFile(std::string("/usr/share/assimp/models/BVH/") + file, 0.01);
    ASSERT_TRUE(m.ok()) << file << ": " << m.status().ToString();
    EXPECT_GT(m->frames.size(), 100u) << file;
  }
  StatusOr<BvhMotion> bvh = ReadBvhFile(path, 1.0);
  ASSERT_TRUE(bvh.ok());
  const BodyModel body = MakeGenericBody();
  RetargetOptions o;
  o.fps = 25;
  o.frames = 150;
  StatusOr<std::vector<std::vector<double>>> poses = RetargetToGenericBody(*bvh, body.skeleton, o);
  ASSERT_TRUE(poses.ok()) << poses.status().ToString();
  const std::vector<std::vector<double>> clip = ResampleMotion(*bvh, 25);
  auto find = [&](const char* name) {
    for (size_t b = 0; b < bvh->skeleton.bones.size(); ++b) {
      if (bvh->skeleton.bones[b].name == name) return int(b);
    }
    return -1;
  };
  struct Limb {
    int from, to;
    const char *bvh_from, *bvh_to;
    double max_mean_deg;
  };
  const Limb limbs[] = {{kLeftHip, kLeftKnee, "LeftUpLeg", "LeftLeg", 1},
                        {kRightHip, kRightKnee, "RightUpLeg", "RightLeg", 1},
                        {kLeftShoulder, kLeftElbow, "LeftArm", "LeftForeArm", 1},
                        {kRightShoulder, kRightElbow, "RightArm", "RightForeArm", 1},
                        {kLeftKnee, kLeftAnkle, "LeftLeg", "LeftFoot", 1},
                        {kLeftElbow, kLeftWrist, "LeftForeArm", "LeftHand", 1}};
  double lowest = 1e9;
  for (const Limb& l : limbs) {
    double sum = 0;
    for (size_t f = 0; f < poses->size(); ++f) {
      const std::vector<Eigen::Vector3d> g = JointPositions(body.skeleton, (*poses)[f]);
      const std::vector<Eigen::Vector3d> b = JointPositions(bvh->skeleton, clip[f]);
      const Eigen::Vector3d dg = (g[l.to] - g[l.from]).normalized();
      const Eigen::Vector3d db = (b[find(l.bvh_to)] - b[find(l.bvh_from)]).normalized();
      sum += std::acos(std::clamp(dg.dot(db), -1.0, 1.0)) / kDeg;
      lowest = std::min({lowest, g[kLeftAnkle].y(), g[kRightAnkle].y()});
    }
    EXPECT_LT(sum / poses->size(), l.max_mean_deg) << GenericJointName(l.from);
    std::printf("  %-12s mean direction error %.2f deg\n", GenericJointName(l.from),
                sum / poses->size());
  }
  EXPECT_NEAR(lowest, JointPositions(body.skeleton, {})[kLeftAnkle].y(), 1e-6);
}

std::string CesiumMan() {
  const char* env = std::getenv("FVV_TEST_DATA");
  return std::string(env ? env : FVV_TEST_DATA_DIR) + "/models/CesiumMan.glb";
}

TEST(Gltf, CesiumManLoadsWith19JointsAndAnimates) {
  struct stat st;
  if (stat(CesiumMan().c_str(), &st) != 0)
    GTEST_SKIP() << CesiumMan() << " absent (third-party data)";
  StatusOr<GltfCharacter> c = LoadGltf(CesiumMan());
  ASSERT_TRUE(c.ok()) << c.status().ToString();
  EXPECT_EQ(c->joint_nodes.size(), 19u);
  EXPECT_GT(c->indices.size() / 3, 1000u);
  EXPECT_GT(c->texture.width, 16u);
  ASSERT_GE(c->animations.size(), 1u);
  EXPECT_GT(c->animations[0].duration, 0.5);
  // The bind pose: rest joint transforms times inverse bind matrices are one
  // common rigid transform (CesiumMan's root turns its Z-up mesh to Y-up).
  const std::vector<Eigen::Matrix4d> rest = c->Skinning(-1, 0);
  const Eigen::Matrix3d r = rest[0].topLeftCorner<3, 3>();
  EXPECT_LT((r * r.transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-4);
  for (const Eigen::Matrix4d& m : rest) EXPECT_LT((m - rest[0]).norm(), 1e-3);
  // The animation moves joints by centimetres to decimetres between two times.
  const std::vector<Eigen::Matrix4d> a = c->NodeWorld(0, 0.1), b = c->NodeWorld(0, 0.6);
  double most = 0;
  for (int node : c->joint_nodes) most = std::max(most, (a[node].col(3) - b[node].col(3)).norm());
  EXPECT_GT(most, 0.05);
  // Sampling wraps: one duration later, the same pose.
  const std::vector<Eigen::Matrix4d> again = c->NodeWorld(0, 0.1 + c->animations[0].duration);
  for (int node : c->joint_nodes) EXPECT_LT((a[node] - again[node]).norm(), 1e-6);
}

TEST(Gltf, BrokenFilesGiveErrors) {
  EXPECT_FALSE(LoadGltf("/nonexistent/character.glb").ok());
  struct stat st;
  if (stat(CesiumMan().c_str(), &st) != 0)
    GTEST_SKIP() << CesiumMan() << " absent (third-party data)";
  std::ifstream in(CesiumMan(), std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string dir = ::testing::TempDir();
  for (size_t cut : {size_t{12}, size_t{600}, bytes.size() / 2, bytes.size() - 1}) {
    const std::string path = dir + "/truncated_" + std::to_string(getpid()) + ".glb";
    std::ofstream(path, std::ios::binary).write(bytes.data(), std::streamsize(cut));
    EXPECT_FALSE(LoadGltf(path).ok()) << "cut at " << cut;
  }
  // A valid glTF without a skin is not a character.
  const std::string path = dir + "/static_" + std::to_string(getpid()) + ".gltf";
  std::ofstream(path)
      << R"({"asset": {"version": "2.0"}, "nodes": [{"name": "a"}], "scenes": [{"nodes": [0]}]})";
  StatusOr<GltfCharacter> c = LoadGltf(path);
  ASSERT_FALSE(c.ok());
  EXPECT_NE(c.status().message().find("skin"), std::string::npos) << c.status().message();
}

// A character file names other files and images; what they claim must not make
// the importer read a directory as a file or allocate for a picture that is not there.
TEST(Gltf, RefusesBuffersThatAreNotFilesAndImagesTooLargeToHold) {
  const std::string dir = ::testing::TempDir() + "/gltf_refs_" + std::to_string(getpid());
  ASSERT_TRUE(MakeDirectories(dir).ok());
  const std::string directory_buffer = dir + "/directory_buffer.gltf";
  std::ofstream(directory_buffer)
      << R"({"asset": {"version": "2.0"}, "buffers": [{"uri": ".", "byteLength": 4}]})";
  StatusOr<GltfCharacter> c = LoadGltf(directory_buffer);
  ASSERT_FALSE(c.ok());
  EXPECT_NE(c.status().message().find("not a regular file"), std::string::npos)
      << c.status().message();

  for (const char* name : {"/empty.glb", "/empty.gltf"}) {
    std::ofstream(dir + name).flush();
    c = LoadGltf(dir + name);
    ASSERT_FALSE(c.ok()) << name;
    EXPECT_NE(c.status().message().find("empty file"), std::string::npos) << c.status().message();
  }

  // A PNG header claiming 10000 x 10000 RGBA pixels (400 MB decoded), and nothing more.
  const std::string huge_image = dir + "/huge_image.gltf";
  std::ofstream(huge_image) << R"({"asset": {"version": "2.0"}, "images": [{"uri":)"
                            << R"( "data:image/png;base64,)"
                            << R"(iVBORw0KGgoAAAANSUhEUgAAJxAAACcQCAYAAAC6TmIn"}]})";
  c = LoadGltf(huge_image);
  ASSERT_FALSE(c.ok());
  EXPECT_NE(c.status().message().find("10000 x 10000 pixels"), std::string::npos)
      << c.status().message();
}

}  // namespace
}  // namespace fvv
