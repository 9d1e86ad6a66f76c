// The image silhouette's margin in resampling: the person network's masks are
// coarse and their outline pixels hold some of what stands behind the actor,
// so a camera's samples come from a little inside them (encoder/encode/
// resample.h); and the mask shrinking that asks for (mask_dilation.h).
#include <gtest/gtest.h>

#include <cmath>

#include "encoder/encode/mask_dilation.h"
#include "encoder/encode/resample.h"

namespace fvv {
namespace {

std::vector<uint8_t> Rect(int w, int h, int x0, int y0, int x1, int y1) {
  std::vector<uint8_t> m(size_t(w) * h, 0);
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) m[size_t(y) * w + x] = 1;
  }
  return m;
}

TEST(MaskDilation, GrowsAndShrinksBySquares) {
  const int w = 20, h = 16;
  // Growing: a pixel becomes a 5x5 square, cut at the image's edge.
  EXPECT_EQ(DilateMask(Rect(w, h, 9, 8, 9, 8).data(), w, h, 2), Rect(w, h, 7, 6, 11, 10));
  EXPECT_EQ(DilateMask(Rect(w, h, 1, 1, 1, 1).data(), w, h, 2), Rect(w, h, 0, 0, 3, 3));
  // Shrinking: a 10x8 block loses two pixels a side; a line 3 wide vanishes.
  EXPECT_EQ(DilateMask(Rect(w, h, 4, 3, 13, 10).data(), w, h, -2), Rect(w, h, 6, 5, 11, 8));
  EXPECT_EQ(DilateMask(Rect(w, h, 2, 5, 17, 7).data(), w, h, -2), std::vector<uint8_t>(w * h, 0));
  // The image's edge does not eat into a block that reaches it.
  EXPECT_EQ(DilateMask(Rect(w, h, 0, 0, 9, 15).data(), w, h, -2), Rect(w, h, 0, 0, 7, 15));
  // Zero leaves the mask as it is.
  const std::vector<uint8_t> m = Rect(w, h, 3, 4, 12, 9);
  EXPECT_EQ(DilateMask(m.data(), w, h, 0), m);
}

// A flat actor facing the camera, the model 3 pixels wider each way than he
// is and his mask 1 pixel looser than him: the model's border falls on the
// background.
struct Scene {
  // `fx`: the focal length (pixels), which sets the actor's size in the
  // image; `atlas`: the texture's size, fine enough to resolve the outline.
  Scene(double fx, uint32_t atlas) {
    const int w = int(std::lround(0.8 * fx)), h = int(std::lround(0.6 * fx));
    camera.width = uint32_t(w), camera.height = uint32_t(h);
    camera.fx = camera.fy = fx, camera.cx = 0.5 * w - 0.5, camera.cy = 0.5 * h - 0.5;
    // Corners at x = +-0.4, y = +-0.3, 2 m away: the middle half of the image
    // each way (pixels 40-120 by 30-90 at fx 200).
    const float xs[2] = {-0.4f, 0.4f}, ys[2] = {-0.3f, 0.3f};
    for (float y : ys) {
      for (float x : xs) {
        mesh.positions.push_back({x, y, 2});
        mesh.normals.push_back({0, 0, -1});
        mesh.uvs.push_back({(x + 0.4f) / 0.8f, (y + 0.3f) / 0.6f});
        positions.emplace_back(x, y, 2);
        normals.emplace_back(0, 0, -1);
      }
    }
    mesh.triangles = {{0, 2, 1}, {1, 2, 3}};
    image.width = silhouette.width = camera.width;
    image.height = silhouette.height = camera.height;
    silhouette.channels = 1;
    // The actor 3 px inside the model on every side; the mask 1 px looser
    // than the actor.
    const int x0 = int(std::ceil(camera.cx - 0.2 * fx)) + 3, x1 = int(camera.cx + 0.2 * fx) - 3;
    const int y0 = int(std::ceil(camera.cy - 0.15 * fx)) + 3, y1 = int(camera.cy + 0.15 * fx) - 3;
    const std::vector<uint8_t> actor = Rect(w, h, x0, y0, x1, y1);
    silhouette.pixels = Rect(w, h, x0 - 1, y0 - 1, x1 + 1, y1 + 1);
    for (uint8_t& v : silhouette.pixels) v *= 255;
    image.pixels.resize(actor.size() * 3);
    for (size_t i = 0; i < actor.size(); ++i) {
      const uint8_t rgb[3] = {uint8_t(actor[i] ? 60 : 30), uint8_t(actor[i] ? 200 : 40),
                              uint8_t(actor[i] ? 50 : 220)};
      for (int k = 0; k < 3; ++k) image.pixels[i * 3 + k] = rgb[k];
    }
    map = MapAtlasTexels(mesh, atlas);
  }
  // Sampled texels, and those with any of the background's blue in them.
  void Sample(const ResampleOptions& o, int* seen, int* blue) const {
    const size_t n = size_t(map.size) * map.size;
    std::vector<uint8_t> rgb(n * 3), mask(n);
    ResampleView(map, mesh, positions, normals, camera, image, silhouette, o, rgb.data(),
                 mask.data());
    *seen = *blue = 0;
    for (size_t t = 0; t < n; ++t) {
      if (!mask[t]) continue;
      ++*seen;
      if (rgb[t * 3 + 2] > 60) ++*blue;
    }
  }
  Camera camera;
  Mesh mesh;
  std::vector<Eigen::Vector3f> positions, normals;
  Image image, silhouette;
  TexelMap map;
};

// A person mask of `w` x `h` set pixels in a larger image.
Image PersonMask(int w, int h) {
  Image m;
  m.width = uint32_t(w + 20), m.height = uint32_t(h + 20), m.channels = 1;
  m.pixels = Rect(w + 20, h + 20, 10, 10, 10 + w - 1, 10 + h - 1);
  for (uint8_t& v : m.pixels) v *= 255;
  return m;
}

TEST(ResampleMargin, TheMarginFollowsTheSilhouettesSource) {
  const Image person = PersonMask(300, 800);
  EXPECT_EQ(SilhouetteMargin(std::nullopt, false, person), kSilhouetteMargin);
  EXPECT_EQ(SilhouetteMargin(std::nullopt, true, person), -2);
  EXPECT_EQ(SilhouetteMargin(3, true, person), 3);
  EXPECT_EQ(SilhouetteMargin(-1, false, person), -1);
}

// Half the network's mask cell, whichever way the person is longer: the
// cells grow with him in the image.
TEST(ResampleMargin, APersonMasksMarginGrowsWithHisSizeInTheImage) {
  EXPECT_EQ(PersonMaskMargin(PersonMask(150, 400)), -1);
  EXPECT_EQ(PersonMaskMargin(PersonMask(800, 300)), -2);
  EXPECT_EQ(PersonMaskMargin(PersonMask(500, 1600)), -4);
  EXPECT_EQ(PersonMaskMargin(PersonMask(20, 40)), -1);  // at least a pixel
  EXPECT_EQ(PersonMaskMargin(PersonMask(0, 0)), -1);    // nobody
}

TEST(ResampleMargin, APersonMasksOutlinePixelsStayOutOfTheTexture) {
  // The actor 634 x 474 px: the mask's margin is -2, its cells about 3 px.
  const Scene scene(1600, 256);
  int seen = 0, blue = 0;
  ResampleOptions person;
  person.person_masks = true;
  ASSERT_EQ(SilhouetteMargin(std::nullopt, true, scene.silhouette), -2);
  scene.Sample(person, &seen, &blue);
  // The actor is 98 % of the model's area; most of it is still sampled.
  EXPECT_GT(seen, int(0.9 * double(scene.map.texel.size())));
  EXPECT_EQ(blue, 0);
  // Grown, as a pixel-accurate silhouette is (unset: the given silhouettes'
  // margin), the same mask lets the model's border take the background.
  scene.Sample(ResampleOptions{}, &seen, &blue);
  EXPECT_GT(blue, 50);
}

}  // namespace
}  // namespace fvv
