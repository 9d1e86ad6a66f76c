// Left and right named the other way round in a camera's sightings
// (encoder/track/sighting_sides.h): exchanged back, whole body, arms or legs,
// from the other cameras' agreement, one camera at a time; sightings that
// agree, and a half of the cameras against the other half, are left alone.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cstdio>
#include <random>

#include "encoder/body/generic_body.h"
#include "encoder/capture/calibration.h"
#include "encoder/track/sighting_sides.h"

namespace fvv {
namespace {

using Frame = std::vector<std::vector<JointSighting>>;

// `count` portrait cameras in a ring around a person-sized volume.
std::vector<Camera> Ring(int count) {
  std::vector<Camera> cameras;
  for (int i = 0; i < count; ++i) {
    const double a = 0.4 + i * 2 * M_PI / count;
    const Eigen::Vector3d centre(3.2 * std::cos(a), 3.2 * std::sin(a), 1.6 + 0.1 * i);
    cameras.push_back(LookAtCamera("cam" + std::to_string(i), 1080, 1920, 1700, centre,
                                   Eigen::Vector3d(0, 0, 1.0), Eigen::Vector3d(0, 0, 1)));
  }
  return cameras;
}

// A standing body facing `facing` radians from +x (its left a quarter turn
// anticlockwise), limbs moved at random, seen by every camera with 3 pixels
// of keypoint noise.
Frame Sight(const std::vector<Camera>& cameras, std::mt19937* rng, double facing = 0) {
  std::uniform_real_distribution<double> u(-1, 1);
  std::normal_distribution<double> noise(0, 3);
  const double ax = 0.3 * u(*rng), ay = 0.3 * u(*rng);
  const Eigen::Vector3d at(ax, ay, 0);
  const std::pair<int, Eigen::Vector3d> left[] = {
      {kLeftShoulder, {0, 0.2, 1.45}}, {kLeftElbow, {0.05, 0.3, 1.15}},
      {kLeftWrist, {0.15, 0.3, 0.9}},  {kLeftHip, {0, 0.1, 0.95}},
      {kLeftKnee, {0.05, 0.12, 0.5}},  {kLeftAnkle, {0, 0.12, 0.08}}};
  Frame frame(cameras.size());
  for (const auto& [joint, place] : left) {
    for (int side : {1, -1}) {
      const double dx = 0.1 * u(*rng), dy = 0.05 * u(*rng);  // in this order in any build
      const Eigen::Vector3d p =
          at + Eigen::AngleAxisd(facing, Eigen::Vector3d::UnitZ()) *
                   Eigen::Vector3d(place.x() + dx, side * place.y() + dy, place.z());
      for (size_t c = 0; c < cameras.size(); ++c) {
        JointSighting s;
        s.joint = side > 0 ? joint : MirrorJoint(joint);
        if (!ProjectPoint(cameras[c], p, &s.pixel)) continue;
        const double nx = noise(*rng), ny = noise(*rng);
        s.pixel += Eigen::Vector2d(nx, ny);
        s.confidence = 0.9;
        frame[c].push_back(s);
      }
    }
  }
  return frame;
}

bool IsLeg(int joint) {
  return joint == kLeftHip || joint == kLeftKnee || joint == kLeftAnkle || joint == kRightHip ||
         joint == kRightKnee || joint == kRightAnkle;
}

void Mislabel(std::vector<JointSighting>* seen, bool arms, bool legs) {
  for (JointSighting& s : *seen) {
    if (IsLeg(s.joint) ? legs : arms) s.joint = MirrorJoint(s.joint);
  }
}

bool Same(const Frame& a, const Frame& b) {
  for (size_t c = 0; c < a.size(); ++c) {
    for (size_t i = 0; i < a[c].size(); ++i) {
      if (a[c][i].joint != b[c][i].joint) return false;
    }
  }
  return true;
}

TEST(SightingSides, MirrorJointIsItsOwnInverse) {
  for (int j = 0; j < kGenericJointCount; ++j) EXPECT_EQ(MirrorJoint(MirrorJoint(j)), j);
  EXPECT_EQ(MirrorJoint(kLeftKnee), kRightKnee);
  EXPECT_EQ(MirrorJoint(kRightWrist), kLeftWrist);
  EXPECT_EQ(MirrorJoint(kHead), kHead);
}

TEST(SightingSides, SightingsThatAgreeAreLeftAlone) {
  const std::vector<Camera> cameras = Ring(4);
  std::mt19937 rng(3);
  for (int f = 0; f < 20; ++f) {
    const Frame truth = Sight(cameras, &rng);
    Frame seen = truth;
    EXPECT_TRUE(ExchangeMislabelledSides(cameras, &seen).exchanges.empty()) << "frame " << f;
    EXPECT_TRUE(Same(seen, truth));
  }
}

TEST(SightingSides, OneCameraMislabelledIsExchangedBack) {
  const std::vector<Camera> cameras = Ring(4);
  std::mt19937 rng(5);
  const struct {
    bool arms, legs;
    SideExchange::Limbs limbs;
  } kCases[] = {{true, true, SideExchange::Limbs::kBody},
                {true, false, SideExchange::Limbs::kArms},
                {false, true, SideExchange::Limbs::kLegs}};
  for (const auto& k : kCases) {
    for (uint32_t bad = 0; bad < 4; ++bad) {
      const Frame truth = Sight(cameras, &rng);
      Frame seen = truth;
      Mislabel(&seen[bad], k.arms, k.legs);
      const SideExchange done = ExchangeMislabelledSides(cameras, &seen);
      ASSERT_EQ(done.exchanges.size(), 1u) << "camera " << bad;
      EXPECT_EQ(done.exchanges[0].camera, bad);
      EXPECT_EQ(done.exchanges[0].limbs, k.limbs) << "camera " << bad;
      EXPECT_LT(2 * done.after_px, done.before_px);
      EXPECT_TRUE(Same(seen, truth)) << "camera " << bad;
    }
  }
}

// A rig of 12: only the cameras that stand out are tried (trying all is
// cubic in cameras), and the decisions are those of trying every camera:
// the same exchanges on frames with one camera named the other way round
// (whole body, arms or legs) and on frames that agree.
TEST(SightingSides, InARigOfTwelveTryingTheCamerasThatStandOutDecidesAsTryingAll) {
  const std::vector<Camera> cameras = Ring(12);
  std::mt19937 rng(7);
  int exchanged = 0;
  for (int f = 0; f < 16; ++f) {
    const Frame truth = Sight(cameras, &rng);
    Frame seen = truth;
    if (f % 4 != 3) Mislabel(&seen[uint32_t(f * 5) % 12], f % 4 != 2, f % 4 != 1);
    Frame all = seen;
    const SideExchange fast = ExchangeMislabelledSides(cameras, &seen);
    const SideExchange slow = ExchangeMislabelledSides(cameras, &all, 12);
    ASSERT_EQ(fast.exchanges.size(), slow.exchanges.size()) << "frame " << f;
    for (size_t i = 0; i < fast.exchanges.size(); ++i) {
      EXPECT_EQ(fast.exchanges[i].camera, slow.exchanges[i].camera) << "frame " << f;
      EXPECT_EQ(fast.exchanges[i].limbs, slow.exchanges[i].limbs) << "frame " << f;
    }
    EXPECT_TRUE(Same(seen, all)) << "frame " << f;
    exchanged += int(fast.exchanges.size());
  }
  // Not a test of nothing: most mislabelled frames are put right.
  EXPECT_GE(exchanged, 8);
}

// Two cameras of six mislabelled in their own ways: one at a time, each step
// must halve the mean disagreement, so where putting the first right leaves
// too much of it to the second, the frame is left as seen (3 of these 10;
// in one a single camera is put right). Never is a camera that named the
// sides right exchanged.
TEST(SightingSides, TwoCamerasMislabelledAmongSixAreExchangedBack) {
  const std::vector<Camera> cameras = Ring(6);
  std::mt19937 rng(9);
  int fixed = 0;
  for (int f = 0; f < 10; ++f) {
    const Frame truth = Sight(cameras, &rng);
    Frame seen = truth;
    Mislabel(&seen[1], true, true);
    Mislabel(&seen[4], false, true);
    const SideExchange done = ExchangeMislabelledSides(cameras, &seen);
    std::printf("frame %d: %zu exchanged, %.1f -> %.1f px\n", f, done.exchanges.size(),
                done.before_px, done.after_px);
    for (const SideExchange::One& e : done.exchanges) {
      EXPECT_TRUE(e.camera == 1 || e.camera == 4) << "frame " << f << ": camera " << e.camera;
    }
    fixed += Same(seen, truth);
  }
  EXPECT_GE(fixed, 6);
}

TEST(SightingSides, TwoCamerasCannotTellWhichIsWrong) {
  const std::vector<Camera> cameras = Ring(2);
  std::mt19937 rng(1);
  Frame seen = Sight(cameras, &rng);
  Mislabel(&seen[0], true, true);
  EXPECT_TRUE(ExchangeMislabelledSides(cameras, &seen).exchanges.empty());
}

// Half of the cameras against the other half: either half could be the one
// named the other way round, so neither is exchanged. The body faces between
// two cameras: none sees it side on, where left and right lie so close that
// exchanging them tells nothing.
TEST(SightingSides, HalfAgainstHalfIsLeftAlone) {
  const std::vector<Camera> cameras = Ring(4);
  std::mt19937 rng(4);
  for (int f = 0; f < 5; ++f) {
    Frame seen = Sight(cameras, &rng, 0.4 + M_PI / 4);
    Mislabel(&seen[0], true, true);
    Mislabel(&seen[2], true, true);
    const Frame before = seen;
    const SideExchange done = ExchangeMislabelledSides(cameras, &seen);
    for (const SideExchange::One& e : done.exchanges) {
      std::printf("frame %d: camera %u exchanged (%d), %.1f -> %.1f px\n", f, e.camera,
                  int(e.limbs), done.before_px, done.after_px);
    }
    EXPECT_TRUE(done.exchanges.empty());
    EXPECT_TRUE(Same(seen, before));
  }
}

}  // namespace
}  // namespace fvv
