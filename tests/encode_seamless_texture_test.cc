// Seamless texture recovery: multi-resolution spline
// blending of camera textures over label regions, and the static texture.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "encoder/encode/encoder.h"
#include "encoder/encode/seamless_texture.h"
#include "encoder/io/image_io.h"
#include "tools/synth/synth.h"
#include "tools/synth/view_score.h"

namespace fvv {
namespace {

struct TwoCameras {
  uint32_t size = 64;
  std::vector<uint8_t> rgb[2], mask[2];
  CameraTextures Textures() const {
    return CameraTextures{size, {rgb[0].data(), rgb[1].data()}, {mask[0].data(), mask[1].data()}};
  }
};

// Camera 0 sees the left 3/4, camera 1 the right 3/4; labels split at x = 32.
TwoCameras Split(uint8_t left, uint8_t right, bool texture) {
  TwoCameras t;
  const size_t n = size_t(t.size) * t.size;
  for (int c = 0; c < 2; ++c) {
    t.rgb[c].assign(n * 3, 0);
    t.mask[c].assign(n, 0);
  }
  for (uint32_t y = 0; y < t.size; ++y) {
    for (uint32_t x = 0; x < t.size; ++x) {
      const size_t i = size_t(y) * t.size + x;
      // Fine detail both cameras share, over each camera's own brightness.
      const int detail = texture ? ((x / 2 + y / 3) % 2) * 40 : 0;
      if (x < 48) {
        t.mask[0][i] = 1;
        for (int k = 0; k < 3; ++k) t.rgb[0][i * 3 + k] = uint8_t(left + detail);
      }
      if (x >= 16) {
        t.mask[1][i] = 1;
        for (int k = 0; k < 3; ++k) t.rgb[1][i * 3 + k] = uint8_t(right + detail);
      }
    }
  }
  return t;
}

std::vector<int16_t> SplitLabels(uint32_t size) {
  std::vector<int16_t> labels(size_t(size) * size);
  for (uint32_t y = 0; y < size; ++y) {
    for (uint32_t x = 0; x < size; ++x) labels[size_t(y) * size + x] = x < 32 ? 0 : 1;
  }
  return labels;
}

TEST(SeamlessTexture, BlendingHidesAStepBetweenCamerasButKeepsFineDetail) {
  const TwoCameras t = Split(60, 140, true);
  const auto labels = SplitLabels(t.size);
  const auto hard = CompositeLabels(t.Textures(), labels);
  const auto soft = BlendSeamless(t.Textures(), labels);
  // The largest change over 4 texels along x: the detail pattern repeats
  // every 4, so what changes is the cameras' brightness.
  auto max_step = [&](const std::vector<uint8_t>& img) {
    int worst = 0;
    for (uint32_t y = 0; y < t.size; ++y) {
      for (uint32_t x = 0; x + 4 < t.size; ++x) {
        const int a = img[(size_t(y) * t.size + x) * 3], b = img[(size_t(y) * t.size + x + 4) * 3];
        worst = std::max(worst, std::abs(a - b));
      }
    }
    return worst;
  };
  EXPECT_EQ(max_step(hard), 80) << "the hard composite jumps by the cameras' difference";
  // Measured 10 (over 4 texels) against the hard composite's 80.
  EXPECT_LT(max_step(soft), 16) << "blended, the step spreads over many texels";
  // Far from the boundary each side keeps its own camera's values, detail included.
  for (uint32_t y = 0; y < t.size; ++y) {
    for (uint32_t x : {2u, 4u, 60u, 62u}) {
      const size_t i = size_t(y) * t.size + x;
      const int expect = x < 32 ? t.rgb[0][i * 3] : t.rgb[1][i * 3];
      EXPECT_NEAR(soft[i * 3], expect, 12) << x << "," << y;
    }
  }
  // The fine detail survives the boundary: its amplitude (40) across x = 30..33.
  for (uint32_t y = 8; y < 56; y += 8) {
    int lo = 255, hi = 0;
    for (uint32_t x = 30; x < 34; ++x) {
      lo = std::min<int>(lo, soft[(size_t(y) * t.size + x) * 3]);
      hi = std::max<int>(hi, soft[(size_t(y) * t.size + x) * 3]);
    }
    EXPECT_GT(hi - lo, 25) << "row " << y;
  }
}

TEST(SeamlessTexture, IdenticalCamerasBlendToThemselves) {
  const TwoCameras t = Split(90, 90, true);
  const auto labels = SplitLabels(t.size);
  const auto soft = BlendSeamless(t.Textures(), labels);
  for (size_t i = 0; i < labels.size(); ++i) {
    EXPECT_NEAR(soft[i * 3], t.rgb[labels[i]][i * 3], 1) << i;
  }
  // Unlabelled texels stay 0; a camera with no labels takes no part.
  std::vector<int16_t> none(labels.size(), -1);
  none[5] = 1;
  const auto one = BlendSeamless(t.Textures(), none);
  EXPECT_EQ(one[0], 0);
}

TEST(StaticTexture, AveragesTheFramesThatLabelledATexel) {
  StaticTexture s(2);
  s.Add({10, 10, 10, 20, 20, 20, 0, 0, 0, 0, 0, 0}, {0, 0, -1, -1});
  s.Add({30, 30, 30, 99, 99, 99, 0, 0, 0, 50, 60, 70}, {1, -1, -1, 0});
  uint8_t rgb[3];
  ASSERT_TRUE(s.Has(0));
  s.Get(0, rgb);
  EXPECT_EQ(rgb[0], 20);
  s.Get(1, rgb);
  EXPECT_EQ(rgb[0], 20) << "frame 2 did not label texel 1";
  EXPECT_FALSE(s.Has(2));
  s.Get(3, rgb);
  EXPECT_EQ(rgb[2], 70);
  EXPECT_EQ(s.Coverage(), (std::vector<uint8_t>{1, 1, 0, 1}));
}

TEST(SeamlessTextureEncoder, FallbackTextureImprovesViewsOfSurfaceAFrameDidNotSee) {
  // Three cameras: in any frame much of the walking actor is unseen, but other
  // frames saw it. Held-out cameras between them look at those parts. Three
  // encodes: unseen texels left to the codec's fill; filled from the static
  // texture alone; from the nearest frames that saw them first (the default).
  const std::string dir = ::testing::TempDir() + "/seamless_test_" + std::to_string(getpid());
  std::system(("rm -rf '" + dir + "'").c_str());
  SynthOptions so;
  so.output_dir = dir + "/cap";
  so.cameras = 3;
  so.frames = 16;
  so.width = 320;
  so.height = 240;
  so.held_out = 3;
  so.link_silhouettes = true;
  ASSERT_TRUE(RunSynth(so).ok());
  EncoderSettings s;
  s.poses = so.output_dir;
  s.atlas_size = 256;
  s.static_texture = dir + "/static.png";
  EncoderSettings static_only = s;
  static_only.temporal_fill_frames = 0;
  static_only.mirror_fill = false;
  static_only.static_texture.clear();
  EncoderSettings plain = static_only;
  plain.fallback_texture = false;
  auto with = EncodeCapture(so.output_dir, dir + "/fallback.fvv", s);
  ASSERT_TRUE(with.ok()) << with.status().ToString();
  auto still = EncodeCapture(so.output_dir, dir + "/static.fvv", static_only);
  ASSERT_TRUE(still.ok()) << still.status().ToString();
  auto without = EncodeCapture(so.output_dir, dir + "/plain.fvv", plain);
  ASSERT_TRUE(without.ok()) << without.status().ToString();
  EXPECT_GT(with->temporal_fill_texels, 1000u);
  EXPECT_GT(still->fallback_texels, with->fallback_texels);
  EXPECT_EQ(still->temporal_fill_texels + still->mirror_fill_texels, 0u);
  std::printf(
      "  texels filled from the nearest frames %llu, the static texture %llu, mirrors %llu\n",
      (unsigned long long)with->temporal_fill_texels, (unsigned long long)with->fallback_texels,
      (unsigned long long)with->mirror_fill_texels);
  EXPECT_EQ(without->fallback_texels + without->temporal_fill_texels + without->mirror_fill_texels,
            0u);
  // The static texture: the atlas, covering at least what some frame saw.
  auto st = ReadImage(s.static_texture);
  ASSERT_TRUE(st.ok()) << st.status().ToString();
  EXPECT_EQ(st->width, 256u);
  double gain = 0, worst = 1e9, over_static = 0;
  int views = 0;
  for (uint32_t camera = 0; camera < 3; ++camera) {
    for (uint32_t frame : {4u, 8u, 12u}) {
      const StatusOr<double> pa =
          HeldOutStreamPsnr(dir + "/plain.fvv", so.output_dir, camera, frame);
      const StatusOr<double> ps =
          HeldOutStreamPsnr(dir + "/static.fvv", so.output_dir, camera, frame);
      const StatusOr<double> pb =
          HeldOutStreamPsnr(dir + "/fallback.fvv", so.output_dir, camera, frame);
      ASSERT_TRUE(pa.ok() && ps.ok() && pb.ok());
      const double a = *pa, b = *pb;
      std::printf(
          "  held-out camera %u, frame %2u: %.2f dB without a fallback, %.2f dB from the "
          "static texture, %.2f dB from the nearest frames first\n",
          camera, frame, a, *ps, b);
      gain += b - a;
      over_static += b - *ps;
      worst = std::min(worst, b - a);
      ++views;
    }
  }
  std::printf("  mean gain %.2f dB over no fallback, %.2f dB over the static texture alone\n",
              gain / views, over_static / views);
  EXPECT_GT(gain / views, 0.15);
  EXPECT_GT(worst, -0.1);
  // This actor's look does not change over the take, so the take's average
  // is as good as the nearest frames' (measured -0.01 dB); where it changes,
  // the nearest frames keep the recent look (TemporalFill's own tests).
  EXPECT_GT(over_static / views, -0.05);
  std::system(("rm -rf '" + dir + "'").c_str());
}

}  // namespace
}  // namespace fvv
