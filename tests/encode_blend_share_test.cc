// The largest share of the reference player's blend a camera can take at a
// surface point (encoder/encode/blend_share.h), against the blend's formula.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "container/geometric_visibility.h"
#include "encoder/encode/blend_share.h"

namespace fvv {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A unit direction at `degrees` around the vertical axis.
Eigen::Vector3f Around(double degrees) {
  const double a = degrees * kPi / 180;
  return Eigen::Vector3f(float(std::cos(a)), 0.0f, float(std::sin(a)));
}

// The blend weight of camera k with the eye on camera c's direction, as
// renderer.frag computes it (visibility 1 past the facing ramp).
double Weight(const std::vector<Eigen::Vector3f>& dir, const std::vector<double>& facing,
              uint32_t c, uint32_t k) {
  namespace gv = geometric_visibility;
  if (facing[k] <= gv::kMinFacing) return 0;
  const double angle = k == c ? 0.0 : std::acos(std::clamp(double(dir[c].dot(dir[k])), -1.0, 1.0));
  return gv::FacingRamp(facing[k]) *
         std::pow(gv::kAngleEpsilon / (angle + gv::kAngleEpsilon), gv::kViewExponent) *
         std::pow(std::max(facing[k], 1e-3), gv::kFacingExponent);
}

TEST(BlendShare, ACameraAloneIsTheWholeBlend) {
  const std::vector<Eigen::Vector3f> dir = {Around(0), Around(90)};
  const std::vector<double> facing = {0.8, 0.9};
  const std::vector<uint8_t> takes = {1, 0};
  EXPECT_DOUBLE_EQ(LargestBlendShare(0, 2, dir.data(), facing.data(), takes.data()), 1.0);
}

TEST(BlendShare, ACameraFacingAwayHasNoShare) {
  const std::vector<Eigen::Vector3f> dir = {Around(0), Around(90)};
  const std::vector<double> facing = {-0.01, 0.9};
  const std::vector<uint8_t> takes = {1, 1};
  EXPECT_EQ(LargestBlendShare(0, 2, dir.data(), facing.data(), takes.data()), 0.0);
}

TEST(BlendShare, TwoCamerasOnOneDirectionShareEqually) {
  const std::vector<Eigen::Vector3f> dir = {Around(30), Around(30)};
  const std::vector<double> facing = {0.7, 0.7};
  const std::vector<uint8_t> takes = {1, 1};
  EXPECT_NEAR(LargestBlendShare(0, 2, dir.data(), facing.data(), takes.data()), 0.5, 1e-6);
}

TEST(BlendShare, IsTheBlendsShareWithTheEyeOnTheCamera) {
  // Five cameras 40 degrees apart, facing the point from squarely to grazing.
  std::vector<Eigen::Vector3f> dir;
  const std::vector<double> facing = {0.95, 0.6, 0.3, 0.12, 0.05};
  for (int k = 0; k < 5; ++k) dir.push_back(Around(40.0 * k));
  const std::vector<uint8_t> takes(5, 1);
  for (uint32_t c = 0; c < 5; ++c) {
    double total = 0;
    for (uint32_t k = 0; k < 5; ++k) total += Weight(dir, facing, c, k);
    EXPECT_NEAR(LargestBlendShare(c, 5, dir.data(), facing.data(), takes.data()),
                Weight(dir, facing, c, c) / total, 1e-9)
        << "camera " << c;
  }
}

TEST(BlendShare, AGrazingCameraBesideASquareOneBarelyShows) {
  // 40 degrees apart: the viewing-angle term alone favours the grazing camera
  // (0.02 / 0.72)^-4, about 6e5 times; its facing (0.12 against 0.95) takes
  // that back, 0.12^8 / 0.95^8 is about 6e-8.
  const std::vector<Eigen::Vector3f> dir = {Around(0), Around(40)};
  const std::vector<double> facing = {0.95, 0.12};
  const std::vector<uint8_t> takes = {1, 1};
  const double grazing = LargestBlendShare(1, 2, dir.data(), facing.data(), takes.data());
  EXPECT_LT(grazing, 0.1);
  EXPECT_GT(LargestBlendShare(0, 2, dir.data(), facing.data(), takes.data()), 0.99);
  // Facing more squarely, the same camera comes to dominate its own direction.
  const std::vector<double> squarer = {0.95, 0.5};
  EXPECT_GT(LargestBlendShare(1, 2, dir.data(), squarer.data(), takes.data()), 0.9);
  // Cameras the player may not take from do not count.
  const std::vector<uint8_t> alone = {0, 1};
  EXPECT_DOUBLE_EQ(LargestBlendShare(1, 2, dir.data(), facing.data(), alone.data()), 1.0);
}

}  // namespace
}  // namespace fvv
