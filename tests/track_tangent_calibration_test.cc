// Camera orientations from the tangents of silhouettes
// (encoder/track/tangent_calibration.h) and the outline hulls they come from
// (encoder/track/outline_hull.h): a moving figure of spheres, filmed by
// cameras turned a few pixels from what their calibration says, gives the
// turns back; masks off at the feet do not turn the rig along what the
// tangents barely measure; too little to measure is an error. A camera whose
// recording runs frames ahead of the others' is found out of step, the first
// camera too.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "encoder/capture/calibration.h"
#include "encoder/track/outline_hull.h"
#include "encoder/track/silhouette_calibration.h"
#include "encoder/track/tangent_calibration.h"
#include "encoder/track/tangent_sync.h"

namespace fvv {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct Sphere {
  Eigen::Vector3d centre;
  double radius;
};

// A figure of `frame`: a trunk of three spheres, a head and two arms and two
// legs whose spheres swing with the frame (y up, standing on y = 0).
std::vector<Sphere> Figure(int frame) {
  const double t = 0.37 * frame;
  const Eigen::Vector3d at(0.3 * std::sin(0.2 * t), 0, 0.25 * std::cos(0.15 * t));
  std::vector<Sphere> s = {{at + Eigen::Vector3d(0, 1.0, 0), 0.17},
                           {at + Eigen::Vector3d(0, 1.25, 0), 0.18},
                           {at + Eigen::Vector3d(0, 1.45, 0), 0.16},
                           {at + Eigen::Vector3d(0, 1.68, 0.02), 0.11}};
  for (int side : {-1, 1}) {
    const double arm = 0.6 + 0.5 * std::sin(t + side), leg = 0.35 * std::sin(1.3 * t + side);
    for (int k = 1; k <= 3; ++k) {
      s.push_back({at + Eigen::Vector3d(side * (0.2 + 0.18 * k * std::sin(arm)),
                                        1.45 - 0.18 * k * std::cos(arm), 0.05 * k * std::cos(t)),
                   0.05});
      s.push_back({at + Eigen::Vector3d(side * 0.1 + 0.05 * k * std::sin(leg), 0.85 - 0.25 * k,
                                        0.25 * k * std::sin(leg)),
                   0.07});
    }
  }
  return s;
}

// The camera's silhouette of the spheres: a pixel is on where its ray meets one.
Image Silhouette(const Camera& camera, const std::vector<Sphere>& figure) {
  Image im;
  im.width = camera.width, im.height = camera.height, im.channels = 1;
  im.pixels.assign(size_t{im.width} * im.height, 0);
  const Eigen::Matrix3d rt = CameraRotation(camera).transpose();
  const Eigen::Vector3d origin = CameraCentre(camera);
  for (uint32_t y = 0; y < im.height; ++y) {
    for (uint32_t x = 0; x < im.width; ++x) {
      const Eigen::Vector3d d =
          (rt * Eigen::Vector3d((x - camera.cx) / camera.fx, (y - camera.cy) / camera.fy, 1))
              .normalized();
      for (const Sphere& s : figure) {
        const Eigen::Vector3d o = origin - s.centre;
        const double b = o.dot(d), c = o.squaredNorm() - s.radius * s.radius;
        if (b * b - c >= 0 && -b > 0) {
          im.pixels[size_t(y) * im.width + x] = 255;
          break;
        }
      }
    }
  }
  return im;
}

// Cameras on a circle of 3.5 m around the figure at `heights`, looking at its
// middle, 240 x 320 portrait.
std::vector<Camera> Ring(const std::vector<double>& heights) {
  std::vector<Camera> cams;
  for (size_t k = 0; k < heights.size(); ++k) {
    const double a = 2 * kPi * double(k) / double(heights.size()) + 0.3;
    cams.push_back(LookAtCamera("cam" + std::to_string(k), 240, 320, 350,
                                Eigen::Vector3d(3.5 * std::cos(a), heights[k], 3.5 * std::sin(a)),
                                Eigen::Vector3d(0, 1.0, 0), Eigen::Vector3d(0, 1, 0)));
  }
  return cams;
}

// Every frame's outline hulls as `filmed` sees the figure, read with `given`'s
// intrinsics (the same here).
std::vector<std::vector<OutlineHull>> Outlines(const std::vector<Camera>& filmed, int frames) {
  std::vector<std::vector<OutlineHull>> out;
  for (int f = 0; f < frames; ++f) {
    std::vector<OutlineHull> hulls;
    for (const Camera& c : filmed) hulls.push_back(MakeOutlineHull(c, Silhouette(c, Figure(f))));
    out.push_back(std::move(hulls));
  }
  return out;
}

// How far apart two orientations of a camera are, in pixels at its focal length.
double PixelsApart(const Camera& a, const Camera& b) {
  return TurnBetween(a, b) * kPi / 180 * a.fx;
}

TEST(OutlineHull, CoversTheMasksPixelsAndMarksTheBorder) {
  Camera cam = LookAtCamera("c", 64, 48, 50, Eigen::Vector3d(0, 0, -3), Eigen::Vector3d(0, 0, 0),
                            Eigen::Vector3d(0, 1, 0));
  Image mask;
  mask.width = 64, mask.height = 48, mask.channels = 1;
  mask.pixels.assign(64 * 48, 0);
  EXPECT_TRUE(MakeOutlineHull(cam, mask).points.empty());
  // A rectangle from (10, 5) to (20, 47): it reaches the bottom row.
  for (int y = 5; y < 48; ++y) {
    for (int x = 10; x <= 20; ++x) mask.pixels[size_t(y) * 64 + size_t(x)] = 255;
  }
  const OutlineHull hull = MakeOutlineHull(cam, mask);
  ASSERT_EQ(hull.points.size(), 4u);
  int border = 0;
  for (size_t i = 0; i < hull.points.size(); ++i) {
    const double x = hull.points[i].x() * cam.fx + cam.cx, y = hull.points[i].y() * cam.fy + cam.cy;
    // The corners of the pixels' squares.
    EXPECT_NEAR(std::min(std::abs(x - 9.5), std::abs(x - 20.5)), 0, 1e-9);
    EXPECT_NEAR(std::min(std::abs(y - 4.5), std::abs(y - 47.5)), 0, 1e-9);
    border += hull.at_border[i];
    EXPECT_EQ(hull.at_border[i] != 0, y > 40) << "point " << i;
  }
  EXPECT_EQ(border, 2);
  auto normalised = [&](double x, double y) {
    return Eigen::Vector2d((x - cam.cx) / cam.fx, (y - cam.cy) / cam.fy);
  };
  EXPECT_TRUE(InsideOutlineHull(hull, normalised(15, 20)));
  EXPECT_FALSE(InsideOutlineHull(hull, normalised(25, 20)));
  EXPECT_FALSE(InsideOutlineHull(hull, normalised(15, 2)));
}

TEST(TangentCalibration, TurnedCamerasAreFoundAgain) {
  const std::vector<Camera> given = Ring({1.6, 2.8, 2.0, 2.5});
  std::vector<Camera> filmed;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> angle(0, 2 * kPi);
  for (const Camera& c : given) {
    const double a = angle(rng);
    filmed.push_back(TurnedByImageShift(c, Eigen::Vector2d(5 * std::cos(a), 5 * std::sin(a))));
  }
  const auto outlines = Outlines(filmed, 24);
  StatusOr<TangentCalibration> r = RefineCamerasFromTangents(given, outlines);
  ASSERT_TRUE(r.ok()) << r.status().message();
  EXPECT_LE(r->held_directions, 1);
  for (size_t c = 0; c < given.size(); ++c) {
    EXPECT_NEAR(PixelsApart(given[c], filmed[c]), 5, 0.01);
    EXPECT_LT(PixelsApart(r->cameras[c], filmed[c]), 1.0) << given[c].name;
    EXPECT_GT(r->before_px[c], 1.5) << given[c].name;
    EXPECT_LT(r->after_px[c], 0.5) << given[c].name;
    EXPECT_GT(r->tangents[c], 24u * 3);
    // The centre stays.
    EXPECT_LT((CameraCentre(r->cameras[c]) - CameraCentre(given[c])).norm(), 1e-9);
  }
  // Calibrated as filmed: nothing to take back.
  const std::vector<double> exact = TangentDistances(filmed, outlines);
  for (double d : exact) EXPECT_LT(d, 0.5);
}

// `mask` grown downwards by `pixels` in every column: a person network that
// takes the shadow at the feet for the actor.
void GrowDown(Image* mask, int pixels) {
  for (uint32_t x = 0; x < mask->width; ++x) {
    int lowest = -1;
    for (uint32_t y = 0; y < mask->height; ++y) {
      if (mask->pixels[size_t(y) * mask->width + x] != 0) lowest = int(y);
    }
    for (int y = lowest + 1; lowest >= 0 && y <= lowest + pixels && y < int(mask->height); ++y) {
      mask->pixels[size_t(y) * mask->width + x] = 255;
    }
  }
}

TEST(TangentCalibration, MasksOffAtTheFeetDoNotTurnTheRig) {
  // Cameras as calibrated, two of them with masks 3 pixels too long at the
  // feet: what the tangents barely measure (turns that move them all alike)
  // must not be bought with that.
  const std::vector<Camera> cams = Ring({1.6, 2.8, 2.0, 2.5});
  std::vector<std::vector<OutlineHull>> outlines;
  for (int f = 0; f < 24; ++f) {
    std::vector<OutlineHull> hulls;
    for (size_t c = 0; c < cams.size(); ++c) {
      Image mask = Silhouette(cams[c], Figure(f));
      if (c % 2 == 0) GrowDown(&mask, 3);
      hulls.push_back(MakeOutlineHull(cams[c], mask));
    }
    outlines.push_back(std::move(hulls));
  }
  TangentCalibrationOptions all;
  all.min_information = 0;
  double held_most = 0, all_most = 0;
  StatusOr<TangentCalibration> held = RefineCamerasFromTangents(cams, outlines);
  StatusOr<TangentCalibration> free = RefineCamerasFromTangents(cams, outlines, all);
  ASSERT_TRUE(held.ok() && free.ok());
  for (size_t c = 0; c < cams.size(); ++c) {
    held_most = std::max(held_most, PixelsApart(held->cameras[c], cams[c]));
    all_most = std::max(all_most, PixelsApart(free->cameras[c], cams[c]));
  }
  EXPECT_GE(held->held_directions, 1);
  EXPECT_LT(held_most, 1.5);
  // What holding them back is for: turned along every direction, the rig goes further.
  EXPECT_GT(all_most, held_most + 1) << "held " << held_most;
}

TEST(TangentCalibration, TooLittleToMeasureIsAnError) {
  const std::vector<Camera> given = Ring({1.6, 2.8, 2.0});
  EXPECT_FALSE(RefineCamerasFromTangents({given[0]}, Outlines({given[0]}, 2)).ok());
  // Two frames: 3 pairs x 2 tangents x 2 residuals x 2 frames = 24 points,
  // but with empty hulls in one camera fewer than 20.
  std::vector<std::vector<OutlineHull>> outlines = Outlines(given, 2);
  for (auto& frame : outlines) frame[2] = OutlineHull{};
  StatusOr<TangentCalibration> r = RefineCamerasFromTangents(given, outlines);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("too few"), std::string::npos) << r.status().message();
}

// Per camera, the hulls of frames 0..count-1 of its recording, which starts
// `ahead[c]` frames into the figure's motion.
std::vector<std::vector<OutlineHull>> Recordings(const std::vector<Camera>& filmed,
                                                 const std::vector<int>& ahead, int count) {
  std::vector<std::vector<OutlineHull>> out(filmed.size());
  for (size_t c = 0; c < filmed.size(); ++c) {
    for (int f = 0; f < count; ++f) {
      out[c].push_back(MakeOutlineHull(filmed[c], Silhouette(filmed[c], Figure(f + ahead[c]))));
    }
  }
  return out;
}

TEST(TangentSync, ACameraFramesAheadIsFound) {
  // cam2 runs 2 frames ahead and every camera is turned 3 pixels: the offsets
  // that bring it in step are +2 for the other three.
  const std::vector<Camera> given = Ring({1.6, 2.8, 2.0, 2.5});
  std::vector<Camera> filmed;
  const std::vector<Eigen::Vector2d> shifts = {{2, -2}, {-3, 0}, {1, 3}, {-2, -2}};
  for (size_t c = 0; c < given.size(); ++c) {
    filmed.push_back(TurnedByImageShift(given[c], shifts[c]));
  }
  TangentSyncOptions o;
  o.range = 3;
  StatusOr<TangentSync> r = SyncFromTangents(given, Recordings(filmed, {0, 0, 2, 0}, 26), o);
  ASSERT_TRUE(r.ok()) << r.status().message();
  EXPECT_EQ(r->offsets, (std::vector<int>{2, 2, 0, 2}));
  EXPECT_LT(r->cost_after, 0.5 * r->cost_before);
  // The first camera out of step: the other three move together.
  r = SyncFromTangents(given, Recordings(filmed, {2, 0, 0, 0}, 26), o);
  ASSERT_TRUE(r.ok()) << r.status().message();
  EXPECT_EQ(r->offsets, (std::vector<int>{0, 2, 2, 2}));
  // In step already: nothing to add.
  r = SyncFromTangents(given, Recordings(filmed, {0, 0, 0, 0}, 26), o);
  ASSERT_TRUE(r.ok()) << r.status().message();
  EXPECT_EQ(r->offsets, (std::vector<int>{0, 0, 0, 0}));
  // A span too short for the range, and outlines of unequal spans.
  EXPECT_FALSE(SyncFromTangents(given, Recordings(filmed, {0, 0, 0, 0}, 8), o).ok());
  auto uneven = Recordings(filmed, {0, 0, 0, 0}, 12);
  uneven[1].pop_back();
  EXPECT_FALSE(SyncFromTangents(given, uneven, o).ok());
}

}  // namespace
}  // namespace fvv
