// The search for one image shift common to every frame
// (encoder/track/silhouette_shift.h): a camera's silhouettes shifted by a
// known amount, with the pose changing and a per-frame error on top, give
// that shift back; aligned ones give none.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "encoder/track/silhouette_shift.h"

namespace fvv {
namespace {

// A stick figure's outline: a trunk ellipse and two limbs whose angles change
// with `phase`, centred at (cx, cy), in a portrait image (the search runs on
// it reduced by 4 for its range of 48 pixels).
Image Figure(double phase, double cx, double cy) {
  Image im;
  im.width = 720, im.height = 1280, im.channels = 1;
  im.pixels.assign(size_t{im.width} * im.height, 0);
  const double a1 = 0.3 + 0.4 * std::sin(phase), a2 = -0.3 + 0.5 * std::cos(1.3 * phase);
  for (uint32_t y = 0; y < im.height; ++y) {
    for (uint32_t x = 0; x < im.width; ++x) {
      const double u = x - cx, v = y - cy;
      bool on = (u * u) / (90.0 * 90.0) + (v * v) / (240.0 * 240.0) <= 1;
      for (double a : {a1, a2}) {
        // A limb 48 px wide and 300 long from the trunk's bottom.
        const double px = u, py = v - 200;
        const double along = px * std::sin(a) + py * std::cos(a);
        const double across = px * std::cos(a) - py * std::sin(a);
        on = on || (along >= 0 && along <= 300 && std::abs(across) <= 24);
      }
      im.pixels[size_t(y) * im.width + x] = on ? 255 : 0;
    }
  }
  return im;
}

TEST(SilhouetteShift, ShiftedIouMatchesItsDefinition) {
  Image a;
  a.width = 40, a.height = 30, a.channels = 1;
  a.pixels.assign(1200, 0);
  for (int y = 5; y < 15; ++y)
    for (int x = 5; x < 15; ++x) a.pixels[size_t(y) * 40 + x] = 255;
  EXPECT_DOUBLE_EQ(ShiftedMaskIou(a, a, 0, 0), 1.0);
  EXPECT_DOUBLE_EQ(ShiftedMaskIou(a, a, 5, 0), 50.0 / 150.0);
  EXPECT_DOUBLE_EQ(ShiftedMaskIou(a, a, 0, -5), 50.0 / 150.0);
  EXPECT_DOUBLE_EQ(ShiftedMaskIou(a, a, 10, 10), 0.0);
  // Moved out of the image, the block still counts as missing.
  EXPECT_DOUBLE_EQ(ShiftedMaskIou(a, a, -20, 0), 0.0);
}

TEST(SilhouetteShift, FindsTheShiftCommonToEveryFrame) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-4, 4);
  for (const Eigen::Vector2d& truth : {Eigen::Vector2d(-13, 7), Eigen::Vector2d(21, 18),
                                       Eigen::Vector2d(0, 0), Eigen::Vector2d(-30, -6)}) {
    SilhouetteShiftSearch search(48);
    for (int f = 0; f < 12; ++f) {
      const double phase = 0.5 * f, cx = 340 + 6 * f, cy = 600 - 4 * f;
      const Image mask = Figure(phase, cx, cy);
      // The fit: off by the camera's shift, by a per-frame error, and a
      // little wrong in its pose.
      const Image fit =
          Figure(phase + 0.1, cx - truth.x() + jitter(rng), cy - truth.y() + jitter(rng));
      search.Add(fit, mask);
    }
    const SilhouetteShift s = search.Best();
    EXPECT_EQ(s.frames, 12);
    std::printf("true shift %+.0f %+.0f: found %+.1f %+.1f, IoU %.3f -> %.3f\n", truth.x(),
                truth.y(), s.pixels.x(), s.pixels.y(), s.iou, s.shifted_iou);
    EXPECT_NEAR(s.pixels.x(), truth.x(), 2.0) << truth.transpose();
    EXPECT_NEAR(s.pixels.y(), truth.y(), 2.0) << truth.transpose();
    EXPECT_GE(s.shifted_iou, s.iou);
    if (truth.norm() > 10) {
      EXPECT_GT(s.shifted_iou, s.iou + 0.1);
    }
  }
}

TEST(SilhouetteShift, NoFramesNoShift) {
  const SilhouetteShift s = SilhouetteShiftSearch(16).Best();
  EXPECT_EQ(s.frames, 0);
  EXPECT_EQ(s.pixels, Eigen::Vector2d::Zero());
}

}  // namespace
}  // namespace fvv
