// The shape-adaptive wavelet transform and shape-adaptive BISK:
// exact round trips, only in-shape texels coded, embeddedness.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "codec/bisk.h"
#include "codec/sa_wavelet.h"

namespace fvv {
namespace {

// A textured image inside an irregular shape: a blob with a hole, a thin
// diagonal line, isolated pixels.
ShapePlane MakeShape(uint32_t w, uint32_t h, uint32_t seed, double coverage = 1.0) {
  ShapePlane p;
  p.width = w, p.height = h;
  p.samples.resize(size_t(w) * h);
  p.mask.resize(size_t(w) * h);
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> noise(-6, 6);
  const double cx = w * 0.45, cy = h * 0.5, r = std::min(w, h) * 0.4 * std::sqrt(coverage);
  for (uint32_t y = 0; y < h; ++y) {
    for (uint32_t x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      const double d = std::hypot(x - cx, (y - cy) * 1.3);
      const bool blob = d < r && d > r * 0.3;
      const bool line = std::abs(int(x) - int(y)) < 1 && x < w / 3;
      const bool dot = (x * 7 + y * 13 + seed) % 97 == 0;
      p.mask[i] = blob || line || dot;
      p.samples[i] = int32_t(128 + 60 * std::sin(x * 0.3) * std::cos(y * 0.2) +
                             ((x / 4 + y / 4) % 2) * 30 + noise(rng));
    }
  }
  return p;
}

size_t Count(const std::vector<uint8_t>& m) {
  size_t n = 0;
  for (uint8_t v : m) n += v != 0;
  return n;
}

double InShapeMse(const ShapePlane& a, const ShapePlane& b, const std::vector<uint8_t>& shape) {
  double s = 0;
  size_t n = 0;
  for (size_t i = 0; i < shape.size(); ++i) {
    if (!shape[i]) continue;
    const double d = double(a.samples[i]) - b.samples[i];
    s += d * d;
    ++n;
  }
  return n ? s / n : 0;
}

TEST(ShapeAdaptiveWavelet, ReversibleKernelsRoundTripExactlyOnOddShapes) {
  for (auto [w, h] :
       std::vector<std::pair<uint32_t, uint32_t>>{{64, 64}, {37, 29}, {1, 9}, {5, 1}}) {
    for (WaveletKernel k : {WaveletKernel::kHaar, WaveletKernel::kLeGall53}) {
      const ShapePlane in = MakeShape(w, h, w + h);
      const int levels = ShapeAdaptiveLevels(w, h) + 1;
      ShapePlane p = in;
      ForwardShapeAdaptive(k, levels, &p);
      // As many coefficients as samples, where the masks say.
      EXPECT_EQ(Count(p.mask), Count(in.mask)) << w << "x" << h;
      EXPECT_EQ(p.mask, ShapeAdaptiveMasks(in.mask, w, h, levels).back());
      InverseShapeAdaptive(k, levels, in.mask, &p);
      for (size_t i = 0; i < in.samples.size(); ++i) {
        if (in.mask[i]) {
          ASSERT_EQ(p.samples[i], in.samples[i]) << w << "x" << h << " at " << i;
        }
      }
    }
  }
}

TEST(Bisk, FullStreamIsLosslessWithTheReversibleKernel) {
  const ShapePlane in = MakeShape(96, 80, 3);
  const int levels = ShapeAdaptiveLevels(96, 80);
  const std::vector<uint8_t> stream = BiskEncode(in, WaveletKernel::kLeGall53, levels);
  ShapePlane out;
  out.width = 96, out.height = 80, out.mask = in.mask;
  BiskDecodeInfo info;
  ASSERT_TRUE(
      BiskDecode(stream.data(), stream.size(), WaveletKernel::kLeGall53, levels, &out, &info).ok());
  EXPECT_FALSE(info.truncated);
  EXPECT_EQ(InShapeMse(in, out, in.mask), 0.0);
  for (size_t i = 0; i < in.mask.size(); ++i) {
    if (!in.mask[i]) {
      ASSERT_EQ(out.samples[i], 0) << "outside the shape";
    }
  }
}

TEST(Bisk, OnlyTheShapeCosts) {
  // The same picture in a quarter of the area costs far fewer bytes.
  const ShapePlane full = MakeShape(96, 96, 5, 1.0), small = MakeShape(96, 96, 5, 0.25);
  const int levels = ShapeAdaptiveLevels(96, 96);
  const size_t a = BiskEncode(full, WaveletKernel::kLeGall53, levels).size();
  const size_t b = BiskEncode(small, WaveletKernel::kLeGall53, levels).size();
  const double ratio_area = double(Count(small.mask)) / Count(full.mask);
  std::printf("  %zu in-shape texels: %zu bytes; %zu texels: %zu bytes\n", Count(full.mask), a,
              Count(small.mask), b);
  EXPECT_LT(double(b) / a, ratio_area * 1.6);
}

TEST(Bisk, EveryPrefixDecodesAndQualityGrowsWithBytes) {
  const ShapePlane in = MakeShape(64, 64, 9);
  const int levels = ShapeAdaptiveLevels(64, 64);
  for (WaveletKernel k : {WaveletKernel::kLeGall53, WaveletKernel::kCdf97}) {
    const std::vector<uint8_t> stream = BiskEncode(in, k, levels);
    double last = 1e18;
    int last_planes = 0;
    for (size_t bytes = 0; bytes <= stream.size();
         bytes += std::max<size_t>(1, stream.size() / 40)) {
      ShapePlane out;
      out.width = 64, out.height = 64, out.mask = in.mask;
      BiskDecodeInfo info;
      ASSERT_TRUE(BiskDecode(stream.data(), bytes, k, levels, &out, &info).ok()) << bytes;
      const double mse = InShapeMse(in, out, in.mask);
      // Monotone, up to the wobble of mid-interval reconstruction next to
      // lossless (squared errors about 1).
      EXPECT_LE(mse, last * 1.02 + 0.25) << "bytes " << bytes;
      EXPECT_GE(info.planes_completed, last_planes);
      last = std::min(last, mse);
      last_planes = info.planes_completed;
    }
    // The whole stream: lossless for 5/3; close for the 9/7 (it rounds).
    ShapePlane out;
    out.width = 64, out.height = 64, out.mask = in.mask;
    ASSERT_TRUE(BiskDecode(stream.data(), stream.size(), k, levels, &out).ok());
    EXPECT_LT(InShapeMse(in, out, in.mask), k == WaveletKernel::kLeGall53 ? 1e-12 : 2.0);
  }
}

TEST(Bisk, BadHeadersAndEmptyPlanes) {
  ShapePlane out;
  out.width = 8, out.height = 8, out.mask.assign(64, 1);
  const uint8_t bad[] = {31, 0, 0};
  EXPECT_EQ(BiskDecode(bad, 3, WaveletKernel::kLeGall53, 1, &out).code(), StatusCode::kCorrupt);
  ShapePlane zero = out;
  zero.samples.assign(64, 0);
  const std::vector<uint8_t> s = BiskEncode(zero, WaveletKernel::kLeGall53, 1);
  EXPECT_EQ(s.size(), 1u);
  ASSERT_TRUE(BiskDecode(s.data(), s.size(), WaveletKernel::kLeGall53, 1, &out).ok());
  for (int32_t v : out.samples) EXPECT_EQ(v, 0);
  ShapePlane wrong = out;
  wrong.mask.resize(10);
  EXPECT_EQ(BiskDecode(s.data(), s.size(), WaveletKernel::kLeGall53, 1, &wrong).code(),
            StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace fvv
