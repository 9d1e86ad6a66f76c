// The predictive multi-view texture scheme: closed loop,
// lossless at full length, rate control, and what prediction saves.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "codec/bisk.h"
#include "codec/colour.h"
#include "codec/predictive_texture.h"
#include "codec/sa_wavelet.h"

namespace fvv {
namespace {

// Cameras seeing overlapping parts of one surface texture, each with its own
// gain and noise, the texture drifting slowly over the frames.
PredictiveGop MakeGop(uint32_t frames, uint32_t cameras, uint32_t size, uint32_t seed) {
  PredictiveGop g;
  g.frames = frames, g.cameras = cameras, g.width = g.height = size;
  const size_t texels = size_t(size) * size;
  g.rgb.resize(frames * cameras * texels * 3);
  g.mask.resize(frames * cameras * texels);
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0, 1.5);
  for (uint32_t t = 0; t < frames; ++t) {
    for (uint32_t c = 0; c < cameras; ++c) {
      const double gain = 1.0 + 0.04 * (double(c) - 1);
      const double centre = size * (0.25 + 0.5 * c / std::max(1u, cameras - 1));
      for (uint32_t y = 0; y < size; ++y) {
        for (uint32_t x = 0; x < size; ++x) {
          const size_t i = (size_t(t) * cameras + c) * texels + size_t(y) * size + x;
          g.mask[i] = std::abs(double(x) - centre) < size * 0.35 && (x + y) % 29 != 0;
          const double base[3] = {120 + 50 * std::sin(x * 0.21 + t * 0.05) * std::cos(y * 0.17),
                                  90.0 + 40.0 * double((x / 6 + y / 6) % 2),
                                  150 + 30 * std::sin(y * 0.1)};
          for (int k = 0; k < 3; ++k) {
            g.rgb[i * 3 + k] =
                uint8_t(std::clamp(std::lround(base[k] * gain + noise(rng)), 0L, 255L));
          }
        }
      }
    }
  }
  return g;
}

double Psnr(const PredictiveGop& g, const std::vector<uint8_t>& rgb) {
  double sse = 0;
  uint64_t n = 0;
  for (size_t i = 0; i < g.mask.size(); ++i) {
    if (!g.mask[i]) continue;
    for (int k = 0; k < 3; ++k) {
      const double d = double(g.rgb[i * 3 + k]) - rgb[i * 3 + k];
      sse += d * d;
    }
    n += 3;
  }
  return 10 * std::log10(255.0 * 255.0 / std::max(sse / n, 1e-9));
}

TEST(PredictiveTexture, ClosedLoopDecodeIsReferencesPlusDifferencesExactly) {
  const PredictiveGop g = MakeGop(3, 3, 48, 1);
  PredictiveEncodeOptions o;
  o.target_bytes = 6000;
  PredictiveDecoded enc;
  auto s = EncodePredictive(g, o, &enc);
  ASSERT_TRUE(s.ok()) << s.status().ToString();
  EXPECT_LE(s->Bytes(), o.target_bytes);
  PredictiveDecoded dec;
  ASSERT_TRUE(DecodePredictive(*s, g, &dec).ok());
  // The decoder rebuilds exactly what the encoder predicted from.
  EXPECT_EQ(dec.yuv, enc.yuv);
  EXPECT_EQ(dec.rgb, enc.rgb);
  const size_t texels = 48 * 48;
  for (uint32_t t = 0; t < 3; ++t) {
    for (uint32_t c = 0; c < 3; ++c) {
      const size_t tc = t * 3 + c;
      for (int k = 0; k < 3; ++k) {
        for (size_t i = 0; i < texels; ++i) {
          if (!g.mask[tc * texels + i]) continue;
          ASSERT_EQ(dec.yuv[tc][k][i],
                    std::clamp(dec.t00[k][i] + dec.r0[t][k][i] + dec.r[tc][k][i], 0, 255));
        }
      }
    }
  }
}

TEST(PredictiveTexture, WholeStreamsAreLosslessInYuv) {
  const PredictiveGop g = MakeGop(2, 3, 40, 2);
  auto s = EncodePredictive(g, PredictiveEncodeOptions());
  ASSERT_TRUE(s.ok());
  PredictiveDecoded dec;
  ASSERT_TRUE(DecodePredictive(*s, g, &dec).ok());
  const size_t texels = 40 * 40;
  for (size_t tc = 0; tc < 6; ++tc) {
    for (size_t i = 0; i < texels; ++i) {
      if (!g.mask[tc * texels + i]) continue;
      const uint8_t* p = &g.rgb[(tc * texels + i) * 3];
      const Yuv yuv = RgbToYuv(ColourSpace::kYCbCr601, p[0], p[1], p[2]);
      ASSERT_EQ(dec.yuv[tc][0][i], yuv.y);
      ASSERT_EQ(dec.yuv[tc][1][i], yuv.u);
      ASSERT_EQ(dec.yuv[tc][2][i], yuv.v);
    }
  }
}

TEST(PredictiveTexture, MoreBytesBetterPictureAndPredictionSaves) {
  const PredictiveGop g = MakeGop(4, 3, 48, 3);
  double last = 0;
  for (uint64_t target : {3000u, 6000u, 12000u}) {
    PredictiveEncodeOptions o;
    o.target_bytes = target;
    PredictiveDecoded rec;
    auto s = EncodePredictive(g, o, &rec);
    ASSERT_TRUE(s.ok());
    EXPECT_LE(s->Bytes(), target);
    EXPECT_GT(s->Bytes(), target * 0.8) << "rate control left bytes unused";
    const double psnr = Psnr(g, rec.rgb);
    std::printf("  %llu bytes: %.2f dB\n", (unsigned long long)s->Bytes(), psnr);
    EXPECT_GT(psnr, last);
    last = psnr;
  }
  // Lossless (in YUV): predictive against every texture coded on its own.
  auto s = EncodePredictive(g, PredictiveEncodeOptions());
  ASSERT_TRUE(s.ok());
  const size_t texels = 48 * 48;
  uint64_t independent = 0;
  for (size_t tc = 0; tc < size_t(g.frames) * g.cameras; ++tc) {
    for (int k = 0; k < 3; ++k) {
      ShapePlane p;
      p.width = p.height = 48;
      p.mask.assign(g.mask.begin() + tc * texels, g.mask.begin() + (tc + 1) * texels);
      p.samples.assign(texels, 0);
      for (size_t i = 0; i < texels; ++i) {
        const uint8_t* px = &g.rgb[(tc * texels + i) * 3];
        const Yuv yuv = RgbToYuv(ColourSpace::kYCbCr601, px[0], px[1], px[2]);
        p.samples[i] = (k == 0 ? yuv.y : k == 1 ? yuv.u : yuv.v) - 128;
      }
      independent += BiskEncode(p, WaveletKernel::kLeGall53, ShapeAdaptiveLevels(48, 48)).size();
    }
  }
  std::printf("  lossless: predictive %llu bytes, each texture on its own %llu bytes\n",
              (unsigned long long)s->Bytes(), (unsigned long long)independent);
  EXPECT_LT(s->Bytes(), independent);
}

TEST(PredictiveTexture, MismatchedShapesAreRefused) {
  PredictiveGop g = MakeGop(1, 2, 16, 4);
  g.mask.pop_back();
  EXPECT_FALSE(EncodePredictive(g, PredictiveEncodeOptions()).ok());
}

}  // namespace
}  // namespace fvv
