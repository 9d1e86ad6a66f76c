// Model-based stereo on a textured plane filmed by cameras a known angle
// apart: a point put off the plane along the key camera's ray is matched back
// onto it; a flat patch, neighbours too far round or too few give no match;
// the reduced luma averages whole blocks; which rigs suit stereo.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "encoder/capture/calibration.h"
#include "encoder/shape/patch_stereo.h"
#include "encoder/shape/surface_tracking.h"

namespace fvv {
namespace {

using Eigen::Vector3d;

// A grey texture on the plane z = 0: smooth noise, a few centimetres a blob.
double Texture(double x, double y) {
  return 128 + 40 * std::sin(31 * x + 3 * std::sin(17 * y)) * std::cos(23 * y - 2 * x) +
         30 * std::sin(53 * x * y + 11 * y);
}

// The plane as `camera` films it (pixel centres at integers), or a flat grey
// where `flat`.
Image Film(const Camera& camera, bool flat) {
  Image im;
  im.width = camera.width, im.height = camera.height, im.channels = 3;
  im.pixels.resize(size_t(im.width) * im.height * 3);
  Eigen::Matrix3d r;
  for (int i = 0; i < 9; ++i) r(i / 3, i % 3) = camera.rotation[i];
  const Vector3d centre(camera.Centre()[0], camera.Centre()[1], camera.Centre()[2]);
  for (uint32_t y = 0; y < im.height; ++y) {
    for (uint32_t x = 0; x < im.width; ++x) {
      const Vector3d ray =
          r.transpose() * Vector3d((x - camera.cx) / camera.fx, (y - camera.cy) / camera.fy, 1);
      const double t = -centre.z() / ray.z();
      const Vector3d hit = centre + t * ray;
      const double v = flat ? 128 : Texture(hit.x(), hit.y());
      const uint8_t g = uint8_t(std::lround(std::clamp(v, 0.0, 255.0)));
      for (int k = 0; k < 3; ++k) im.pixels[(size_t(y) * im.width + x) * 3 + k] = g;
    }
  }
  return im;
}

// `count` cameras 3 m from the plane's origin, `degrees` apart about it.
StereoViews Views(double degrees, bool flat, int count = 3) {
  StereoViews v;
  for (int i = 0; i < count; ++i) {
    const double rad = (i - 0.5 * (count - 1)) * degrees * 3.14159265358979 / 180;
    const Vector3d centre(3 * std::sin(rad), 0.2, 3 * std::cos(rad));
    const Camera c = LookAtCamera("c", 320, 240, 300, centre, Vector3d::Zero(), Vector3d(0, 1, 0));
    v.cameras.push_back(c);
    v.centres.push_back(centre);
    v.grey.push_back(Grey(Film(c, flat)));
  }
  return v;
}

TEST(PatchStereo, MatchesAPointOffThePlaneBackOntoIt) {
  const StereoViews views = Views(30, false);
  const Vector3d normal(0, 0, 1);
  int matched = 0;
  double worst = 0;
  for (double off : {-0.03, -0.015, 0.02, 0.04}) {
    for (const Vector3d& on :
         {Vector3d(0, 0, 0), Vector3d(0.1, -0.05, 0), Vector3d(-0.12, 0.1, 0)}) {
      // Off the plane: the match lies on the key camera's ray through it.
      const Vector3d p = on + off * normal;
      const StereoTarget t =
          MatchAlongKeyRay(views, {1, 1, 1}, p, normal, LocalSurface{}, 0.06, PatchStereoOptions());
      if (!t.valid) continue;
      ++matched;
      // The match lies on the plane (its height), where the ray crosses it.
      worst = std::max(worst, std::abs(t.point.z()));
      EXPECT_GT(t.score, 0.8);
    }
  }
  std::printf("  %d of 12 points matched, the farthest %.2f mm off the plane\n", matched,
              1000 * worst);
  EXPECT_GE(matched, 10);
  // A pixel is about 1 cm here; the parabola places the peak within a few mm.
  EXPECT_LT(worst, 0.004);
}

TEST(PatchStereo, NoMatchOnAFlatPatchOrBeyondTheNeighbourAngleOrWithTooFewNeighbours) {
  const Vector3d p(0, 0, 0.02), normal(0, 0, 1);
  const PatchStereoOptions defaults;
  EXPECT_TRUE(
      MatchAlongKeyRay(Views(30, false), {1, 1, 1}, p, normal, LocalSurface{}, 0.06, defaults)
          .valid);
  EXPECT_FALSE(
      MatchAlongKeyRay(Views(30, true), {1, 1, 1}, p, normal, LocalSurface{}, 0.06, defaults)
          .valid);
  // 40 degrees apart: the outer two are 40 from the middle one (within the
  // default 0.9 rad) and 80 from each other. The key camera facing the point
  // best is the middle one, so both are its neighbours; seen from an outer
  // camera it would have one.
  EXPECT_TRUE(
      MatchAlongKeyRay(Views(40, false), {1, 1, 1}, p, normal, LocalSurface{}, 0.06, defaults)
          .valid);
  // 60 degrees apart: beyond the default angle, and matched when allowed.
  const StereoViews wide = Views(60, false);
  EXPECT_FALSE(MatchAlongKeyRay(wide, {1, 1, 1}, p, normal, LocalSurface{}, 0.06, defaults).valid);
  PatchStereoOptions wider;
  wider.max_angle = 1.2;
  const StereoTarget t = MatchAlongKeyRay(wide, {1, 1, 1}, p, normal, LocalSurface{}, 0.06, wider);
  ASSERT_TRUE(t.valid);
  EXPECT_LT(std::abs(t.point.z()), 0.004);
  // One neighbour is too few by default (a false peak would stand alone),
  // and enough when asked for: a camera that does not see the point is no
  // neighbour, and two cameras have one.
  EXPECT_FALSE(
      MatchAlongKeyRay(Views(30, false), {1, 1, 0}, p, normal, LocalSurface{}, 0.06, defaults)
          .valid);
  EXPECT_FALSE(
      MatchAlongKeyRay(Views(30, false, 2), {1, 1}, p, normal, LocalSurface{}, 0.06, defaults)
          .valid);
  PatchStereoOptions one;
  one.min_neighbours = 1;
  EXPECT_TRUE(
      MatchAlongKeyRay(Views(30, false, 2), {1, 1}, p, normal, LocalSurface{}, 0.06, one).valid);
  EXPECT_FALSE(
      MatchAlongKeyRay(Views(30, false), {0, 1, 0}, p, normal, LocalSurface{}, 0.06, one).valid);
}

TEST(PatchStereo, ReducedLumaAveragesWholeBlocks) {
  Image im;
  im.width = 5, im.height = 3, im.channels = 3;
  im.pixels.assign(5 * 3 * 3, 0);
  for (int x = 0; x < 4; ++x) {
    for (int k = 0; k < 3; ++k) im.pixels[size_t(x) * 3 + k] = uint8_t(x < 2 ? 200 : 100);
  }
  const GreyImage g = Grey(im, 2);
  ASSERT_EQ(g.width, 2);
  ASSERT_EQ(g.height, 1);
  EXPECT_NEAR(g.pixels[0], 100.0, 0.01);  // two of four pixels at 200
  EXPECT_NEAR(g.pixels[1], 50.0, 0.01);
  EXPECT_NEAR(Grey(im).pixels[0], 200.0, 0.01);
}

// A ring of `count` cameras 3.6 m from an actor standing at the origin,
// `width` pixels wide (4:3) with a focal length of 1.125 widths.
std::vector<Camera> Ring(int count, uint32_t width) {
  std::vector<Camera> out;
  for (int i = 0; i < count; ++i) {
    const double a = 2 * 3.14159265358979 * i / count;
    out.push_back(LookAtCamera("r", width, width * 3 / 4, 1.125 * width,
                               Vector3d(3.6 * std::sin(a), 1.3, 3.6 * std::cos(a)),
                               Vector3d(0, 0.9, 0), Vector3d(0, 1, 0)));
  }
  return out;
}

TEST(PatchStereo, RigsThatSuitStereo) {
  const Vector3d actor(0, 0.9, 0);
  const SurfaceTrackingOptions o;
  EXPECT_TRUE(RigSuitsStereo(Ring(8, 640), actor, o));    // 45 degrees apart, 5 mm a pixel
  EXPECT_TRUE(RigSuitsStereo(Ring(8, 1280), actor, o));   // worked at 640 pixels: the same
  EXPECT_FALSE(RigSuitsStereo(Ring(8, 320), actor, o));   // 10 mm a pixel
  EXPECT_FALSE(RigSuitsStereo(Ring(6, 640), actor, o));   // 60 degrees apart
  EXPECT_FALSE(RigSuitsStereo(Ring(4, 1280), actor, o));  // 90 degrees apart
  // Far off to one side, the ring's cameras no longer stand 45 degrees apart
  // seen from the actor: those behind him see each other's directions closer,
  // the near ones wider.
  EXPECT_FALSE(RigSuitsStereo(Ring(8, 640), Vector3d(2.5, 0.9, 0), o));
  EXPECT_FALSE(RigSuitsStereo({}, actor, o));
}

}  // namespace
}  // namespace fvv
