// Model registration from feature points: the feature
// file, triangulation, and the pose and proportions fitted to joint centres of
// a synthetic capture whose actor is 10 % taller than the generic body.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <nlohmann/json.hpp>
#include <random>

#include "encoder/body/kinematics.h"
#include "encoder/capture/capture.h"
#include "encoder/encode/pose_file.h"
#include "encoder/io/image_io.h"
#include "encoder/track/feature_registration.h"
#include "encoder/track/features.h"
#include "tools/synth/synth.h"

namespace fvv {
namespace {

class FeatureRegistrationTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = ::testing::TempDir() + "/feature_registration_test_" + std::to_string(getpid());
    std::system(("rm -rf '" + dir_ + "'").c_str());
    SynthOptions o;
    o.output_dir = dir_ + "/cap";
    o.frames = 6;
    o.width = 320;
    o.height = 240;
    o.held_out = 0;
    o.stature = 1.1;
    status_ = RunSynth(o).status();
  }
  static void TearDownTestSuite() { std::system(("rm -rf '" + dir_ + "'").c_str()); }
  void SetUp() override {
    ASSERT_TRUE(status_.ok()) << status_.ToString();
    auto cap = LoadCapture(dir_ + "/cap");
    ASSERT_TRUE(cap.ok());
    for (const auto& c : cap->cameras) cameras_.push_back(c.calibration);
    auto f = LoadFeatures(dir_ + "/cap/truth/features.json", cameras_, cap->frame_count);
    ASSERT_TRUE(f.ok()) << f.status().ToString();
    features_ = *f;
    auto truth = ReadFileBytes(dir_ + "/cap/truth/truth.json", 64u << 20);
    ASSERT_TRUE(truth.ok());
    truth_ = nlohmann::json::parse(truth->begin(), truth->end());
  }
  Eigen::Vector3d TrueJoint(uint32_t frame, const std::string& name) const {
    const auto& p = truth_["frames"][frame]["joints"][name];
    return Eigen::Vector3d(p[0].get<double>(), p[1].get<double>(), p[2].get<double>());
  }
  // The features with Gaussian pixel noise.
  FeatureSet Noisy(double sigma, uint32_t seed) const {
    FeatureSet out = features_;
    std::mt19937 rng(seed);
    std::normal_distribution<double> n(0.0, sigma);
    for (auto& [f, points] : out.frames) {
      for (auto& [name, views] : points) {
        for (auto& [c, p] : views) p += Eigen::Vector2d(n(rng), n(rng));
      }
    }
    return out;
  }

  static std::string dir_;
  static Status status_;
  std::vector<Camera> cameras_;
  FeatureSet features_;
  nlohmann::json truth_;
};
std::string FeatureRegistrationTest::dir_;
Status FeatureRegistrationTest::status_;

TEST_F(FeatureRegistrationTest, FileRoundTripsAndBadFilesAreNamed) {
  const std::string text = FeaturesToJson(features_, cameras_);
  auto again = ParseFeatures(text, cameras_, 6, "f.json");
  ASSERT_TRUE(again.ok()) << again.status().ToString();
  EXPECT_EQ(again->frames.size(), 6u);
  EXPECT_EQ(again->frames.at(2).at("l_knee").size(), features_.frames.at(2).at("l_knee").size());
  const auto bad = [&](const std::string& t, const std::string& says) {
    auto r = ParseFeatures(t, cameras_, 6, "f.json");
    ASSERT_FALSE(r.ok()) << t;
    EXPECT_NE(r.status().message().find(says), std::string::npos) << r.status().message();
  };
  bad("{", "not JSON");
  bad(R"({"features": 3})", "expected");
  bad(R"({"features": [{"frame": 0, "camera": "nope", "points": {}}]})", "no camera \"nope\"");
  bad(R"({"features": [{"frame": 9, "camera": "cam00", "points": {}}]})", "beyond");
  bad(R"({"features": [{"frame": 0, "camera": "cam00", "points": {"nose": [1, 2]}}]})",
      "not a feature name");
  bad(R"({"features": [{"frame": 0, "camera": "cam00", "points": {"l_knee": [1e6, 2]}}]})",
      "outside");
  bad(R"({"features": [{"frame": 0, "camera": "cam00", "points": {"l_knee": "x"}}]})",
      "expected [x, y]");
}

TEST_F(FeatureRegistrationTest, TriangulatedJointsMatchTheTruth) {
  for (double sigma : {0.0, 1.0}) {
    const FeatureSet f = Noisy(sigma, 7);
    double worst = 0, sum = 0;
    int count = 0;
    for (const auto& [frame, points] : f.frames) {
      for (const auto& [name, p] : TriangulateFeatures(points, cameras_)) {
        const double e = (p.position - TrueJoint(frame, name)).norm();
        worst = std::max(worst, e);
        sum += e;
        ++count;
      }
    }
    std::printf("  pixel noise %.1f: %d joints, mean error %.2f mm, max %.2f mm\n", sigma, count,
                sum / count * 1e3, worst * 1e3);
    EXPECT_GT(count, 6 * 15);
    EXPECT_LT(worst, sigma == 0 ? 1e-4 : 0.025);
  }
  // A mislabelled view is left out by its reprojection error: the point is
  // made from the other views, where the truth is.
  auto points = features_.frames.at(0);
  ASSERT_GE(points["l_knee"].size(), 3u);
  const size_t views = points["l_knee"].size();
  points["l_knee"].begin()->second += Eigen::Vector2d(40, 0);
  const auto kept = TriangulateFeatures(points, cameras_);
  ASSERT_EQ(kept.count("l_knee"), 1u);
  EXPECT_EQ(kept.at("l_knee").views, int(views) - 1);
  EXPECT_LT((kept.at("l_knee").position - TrueJoint(0, "l_knee")).norm(), 1e-3);
  // With two views there is no majority: the point is left out.
  auto pair = features_.frames.at(0);
  while (pair["l_knee"].size() > 2) pair["l_knee"].erase(std::prev(pair["l_knee"].end()));
  pair["l_knee"].begin()->second += Eigen::Vector2d(40, 0);
  EXPECT_EQ(TriangulateFeatures(pair, cameras_).count("l_knee"), 0u);
}

TEST_F(FeatureRegistrationTest, PoseAndProportionsFitTheJoints) {
  const FeatureSet f = Noisy(1.0, 11);
  std::vector<double> previous;
  BodyShape shape;
  double init_sum = 0, fit_sum = 0, joint_sum = 0, joint_max = 0;
  int joints = 0;
  for (uint32_t frame = 0; frame < 6; ++frame) {
    const auto points = TriangulateFeatures(f.frames.at(frame), cameras_);
    // Frame 0 from the analytic initialisation with proportions fitted; later
    // frames from the previous pose, proportions kept.
    RegistrationOptions o;
    o.fit_shape = frame == 0;
    auto r = RegisterSkeleton(points, shape, frame == 0 ? std::vector<double>() : previous, o);
    ASSERT_TRUE(r.ok()) << r.status().ToString();
    if (frame == 0) {
      shape = r->shape;
      std::printf(
          "  frame 0: joint rms %.1f cm after the analytic initialisation, %.2f cm fitted\n",
          r->initial_rms_m * 100, r->rms_m * 100);
      EXPECT_LT(r->initial_rms_m, 0.08) << "the analytic initialisation is far off";
      // The actor is 10 % taller: the fitted limb lengths say so.
      for (int s : {kSegLeftThigh, kSegRightShank, kSegLeftUpperArm}) {
        EXPECT_NEAR(r->shape.length[s], 1.1, 0.08) << GenericSegmentName(s);
      }
    }
    init_sum += r->initial_rms_m;
    fit_sum += r->rms_m;
    previous = r->dofs;
    const auto pos = JointPositions(MakeGenericSkeleton(shape), r->dofs);
    const Skeleton skel = MakeGenericSkeleton(shape);
    for (size_t b = 0; b < skel.bones.size(); ++b) {
      const double e = (pos[b] - TrueJoint(frame, skel.bones[b].name)).norm();
      joint_sum += e;
      joint_max = std::max(joint_max, e);
      ++joints;
    }
  }
  std::printf(
      "  6 frames: joint rms to the features %.2f cm (%.2f cm from each frame's start); all 17 "
      "joints against the truth: mean %.2f cm, max %.2f cm\n",
      fit_sum / 6 * 100, init_sum / 6 * 100, joint_sum / joints * 100, joint_max * 100);
  EXPECT_LT(fit_sum / 6, 0.01);
  EXPECT_LE(fit_sum, init_sum) << "registration left the joints further than it found them";
  EXPECT_LT(joint_sum / joints, 0.012);
  EXPECT_LT(joint_max, 0.04);
  // Too few joints: a clear error.
  std::map<std::string, Feature3D> few;
  few["l_knee"] = Feature3D();
  EXPECT_EQ(RegisterSkeleton(few, BodyShape(), {}).status().code(), StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace fvv
