// The tracker's span rasteriser (encoder/track/silhouette_raster.h) against
// its definition, the per-pixel test over each triangle's bounding box, on
// random triangles of every size: slivers, sub-pixel ones, ones with vertices
// on pixel centres and ones far outside the image.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "encoder/track/silhouette_raster.h"

namespace fvv {
namespace {

using Eigen::Vector2f;

// The definition: every pixel of the clipped bounding box tested on its own.
void ReferenceRaster(const std::vector<uint32_t>& tris, const std::vector<Vector2f>& px, int w,
                     int h, uint8_t* out) {
  for (size_t t = 0; t + 2 < tris.size(); t += 3) {
    const Vector2f a = px[tris[t]], b = px[tris[t + 1]], c = px[tris[t + 2]];
    const float area = (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
    if (!(area < 0)) continue;
    const float inv = 1.0f / area;
    // Every pixel centre of the triangle's box within the image.
    auto clip = [](double v, int n) { return std::min(std::max(v, -1.0), double(n)); };
    const int x0 = std::max(0, int(std::ceil(clip(std::min({a.x(), b.x(), c.x()}), w))));
    const int x1 = std::min(w - 1, int(std::floor(clip(std::max({a.x(), b.x(), c.x()}), w))));
    const int y0 = std::max(0, int(std::ceil(clip(std::min({a.y(), b.y(), c.y()}), h))));
    const int y1 = std::min(h - 1, int(std::floor(clip(std::max({a.y(), b.y(), c.y()}), h))));
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        if (PixelInTriangle(a, b, c, inv, x, y)) out[size_t(y) * w + x] = 1;
      }
    }
  }
}

// One triangle at a time so a mismatch names the triangle.
void ExpectSameAsDefinition(const Vector2f& a, const Vector2f& b, const Vector2f& c, int w, int h,
                            int* pixels_set) {
  const std::vector<Vector2f> px = {a, b, c};
  const std::vector<uint32_t> tris = {0, 1, 2};
  std::vector<uint8_t> got(size_t(w) * h, 0), want(size_t(w) * h, 0);
  RasterBox box{w, h, -1, -1};
  RasteriseSilhouette(tris, px, w, h, got.data(), &box);
  ReferenceRaster(tris, px, w, h, want.data());
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      ASSERT_EQ(got[i], want[i]) << "pixel " << x << "," << y << " of triangle (" << a.x() << ","
                                 << a.y() << ") (" << b.x() << "," << b.y() << ") (" << c.x() << ","
                                 << c.y() << ")";
      *pixels_set += want[i];
      if (got[i]) {  // the box covers every pixel drawn
        ASSERT_TRUE(x >= box.x0 && x <= box.x1 && y >= box.y0 && y <= box.y1);
      }
    }
  }
}

TEST(SilhouetteRaster, EqualsThePerPixelDefinitionOnRandomTriangles) {
  constexpr int kW = 67, kH = 53;
  std::mt19937 rng(5);
  int pixels = 0, drawn = 0;
  for (int i = 0; i < 30000; ++i) {
    // Sizes from a tenth of a pixel to twice the image; some on the pixel grid.
    const float scale = std::pow(10.0f, std::uniform_real_distribution<float>(-1, 2.2f)(rng));
    std::uniform_real_distribution<float> centre(-10, kW + 10), off(-scale, scale);
    const float cx = centre(rng), cy = centre(rng) * kH / kW;
    Vector2f v[3];
    for (Vector2f& p : v) {
      p = {cx + off(rng), cy + off(rng)};
      if (i % 5 == 0) p = {std::round(p.x()), std::round(p.y())};
      if (i % 7 == 0) p.y() = std::round(cy);  // horizontal edges
    }
    int before = pixels;
    ExpectSameAsDefinition(v[0], v[1], v[2], kW, kH, &pixels);
    ExpectSameAsDefinition(v[0], v[2], v[1], kW, kH, &pixels);  // one of the two faces front
    if (HasFatalFailure()) return;
    drawn += pixels > before;
  }
  // The inputs reach the interesting cases: many triangles draw something.
  EXPECT_GT(drawn, 10000);
  EXPECT_GT(pixels, 1000000);
}

// A mesh-like batch in one call (shared vertices, a count that is not a
// multiple of four): the path that culls four triangles at a time.
TEST(SilhouetteRaster, BatchesEqualTheDefinition) {
  constexpr int kW = 160, kH = 120;
  std::mt19937 rng(11);
  for (int round = 0; round < 40; ++round) {
    std::uniform_real_distribution<float> pos(-20, kW + 20), jitter(-4, 4);
    std::vector<Vector2f> px;
    for (int i = 0; i < 300; ++i) px.push_back({pos(rng), pos(rng) * kH / kW});
    std::vector<uint32_t> tris;
    std::uniform_int_distribution<uint32_t> pick(0, 299);
    const int count = 1001 + round;
    for (int i = 0; i < count; ++i) {
      const uint32_t a = pick(rng);
      // Mostly small triangles: neighbours of a vertex moved a few pixels.
      px.push_back(px[a] + Vector2f(jitter(rng), jitter(rng)));
      px.push_back(px[a] + Vector2f(jitter(rng), jitter(rng)));
      if (round % 4 == 3) px.back() = {1e12f, -3e9f};  // far behind-camera projections
      tris.insert(tris.end(), {a, uint32_t(px.size() - 2), uint32_t(px.size() - 1)});
    }
    std::vector<uint8_t> got(size_t(kW) * kH, 0), want(size_t(kW) * kH, 0);
    RasterBox box{kW, kH, -1, -1};
    RasteriseSilhouette(tris, px, kW, kH, got.data(), &box);
    ReferenceRaster(tris, px, kW, kH, want.data());
    ASSERT_EQ(got, want) << "round " << round;
    EXPECT_GT(std::count(want.begin(), want.end(), 1), 500);
    RasterBox ref_box{kW, kH, -1, -1};
    for (size_t t = 0; t < tris.size(); t += 3) {  // the box: union of the drawn triangles' boxes
      RasterBox one{kW, kH, -1, -1};
      std::vector<uint8_t> scratch(size_t(kW) * kH, 0);
      RasteriseSilhouette({tris[t], tris[t + 1], tris[t + 2]}, px, kW, kH, scratch.data(), &one);
      ref_box = {std::min(ref_box.x0, one.x0), std::min(ref_box.y0, one.y0),
                 std::max(ref_box.x1, one.x1), std::max(ref_box.y1, one.y1)};
    }
    EXPECT_EQ(box.x0, ref_box.x0);
    EXPECT_EQ(box.y0, ref_box.y0);
    EXPECT_EQ(box.x1, ref_box.x1);
    EXPECT_EQ(box.y1, ref_box.y1);
  }
}

TEST(SilhouetteRaster, BackFacesAndDegenerateTrianglesDrawNothing) {
  const std::vector<Vector2f> px = {{2, 2}, {20, 3}, {5, 18}, {30, 30}, {30, 30}};
  std::vector<uint8_t> img(40 * 40, 0);
  RasterBox box{40, 40, -1, -1};
  // (2,2) (20,3) (5,18) has positive area in y-down coordinates: a back face.
  RasteriseSilhouette({0, 1, 2, 3, 4, 0, 3, 3, 4}, px, 40, 40, img.data(), &box);
  EXPECT_EQ(std::count(img.begin(), img.end(), 1), 0);
  EXPECT_GT(box.x0, box.x1);
  RasteriseSilhouette({0, 2, 1}, px, 40, 40, img.data(), &box);  // the front face
  EXPECT_GT(std::count(img.begin(), img.end(), 1), 100);
  EXPECT_EQ(box.x0, 2);
  EXPECT_EQ(box.x1, 20);
}

}  // namespace
}  // namespace fvv
