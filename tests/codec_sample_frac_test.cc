// Fractional samples (format version 7): YCbCr with p fractional bits through
// colour conversion, coding, the block file and the decoder's checks.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "codec/block_codec.h"
#include "codec/block_syntax.h"
#include "codec/colour.h"

namespace fvv {
namespace {

// An RGB image with smooth gradients, edges and fine texture in every channel,
// so that all of Y, U and V carry detail.
std::vector<uint8_t> TestRgb(const Shape4D& shape, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> noise(-3, 3);
  std::vector<uint8_t> rgb(shape.count() * 3);
  size_t i = 0;
  for (uint32_t tc = 0; tc < shape.frames() * shape.cameras(); ++tc)
    for (uint32_t y = 0; y < shape.height(); ++y)
      for (uint32_t x = 0; x < shape.width(); ++x, ++i)
        for (int c = 0; c < 3; ++c) {
          const double v = 128 + 90 * std::sin(0.05 * x * (c + 1) + 0.03 * y + 0.4 * tc + c) +
                           (((x / 16 + y / 16 + c) & 1) ? 20 : -20);
          rgb[3 * i + c] =
              static_cast<uint8_t>(std::clamp(static_cast<int>(v) + noise(rng), 0, 255));
        }
  return rgb;
}

double RgbPsnr(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  double sum = 0;
  for (size_t i = 0; i < a.size(); ++i) sum += (double(a[i]) - b[i]) * (double(a[i]) - b[i]);
  return PsnrFromMse(sum / double(a.size()));
}

// RGB PSNR of coding `rgb` at `bpp` with samples of `frac` fractional bits.
double CodedRgbPsnr(const std::vector<uint8_t>& rgb, const Shape4D& shape, int frac, double bpp) {
  const Block block =
      BlockFromRgb(rgb.data(), shape, ColourSpace::kYCbCr601, ChromaFormat::k444, frac);
  EXPECT_EQ(block.sample_frac, frac);
  EncodeSettings s;
  s.rate_value = bpp;
  s.prune_isolated = false;  // the sample precision alone: pruning helps both, the weaker more
  auto enc = EncodeBlock(block, nullptr, s);
  EXPECT_TRUE(enc.ok()) << enc.status().ToString();
  if (!enc.ok()) return 0;
  EXPECT_EQ(enc->params.sample_frac, frac);
  auto dec = DecodeBlock(*enc, DecodeBudget{}, SerialRunner);
  EXPECT_TRUE(dec.ok()) << dec.status().ToString();
  if (!dec.ok()) return 0;
  EXPECT_EQ(dec->sample_frac, frac);
  std::vector<uint8_t> out(rgb.size());
  BlockToRgb(*dec, out.data());
  return RgbPsnr(rgb, out);
}

// The vector row conversion is the scalar one, for every precision, on
// samples across their whole range (and on row lengths that leave a tail).
TEST(SampleFrac, RowConversionMatchesScalarAtEveryPrecision) {
  std::mt19937 rng(5);
  for (int frac = 0; frac <= kMaxSampleFrac; ++frac) {
    std::uniform_int_distribution<int32_t> d(0, 255 << frac);
    for (uint32_t n : {1u, 15u, 16u, 37u, 200u}) {
      std::vector<int32_t> y(n), u(n), v(n);
      for (uint32_t i = 0; i < n; ++i) y[i] = d(rng), u[i] = d(rng), v[i] = d(rng);
      if (n > 2) y[0] = u[0] = v[0] = 0, y[1] = u[1] = v[1] = 255 << frac;
      std::vector<uint8_t> rgb(3 * n);
      YcbcrRowToRgb8(y.data(), u.data(), v.data(), n, rgb.data(), frac);
      for (uint32_t i = 0; i < n; ++i) {
        const Rgb8 p = YuvToRgb(ColourSpace::kYCbCr601, y[i], u[i], v[i], frac);
        ASSERT_EQ(rgb[3 * i], p.r) << "frac " << frac << " texel " << i;
        ASSERT_EQ(rgb[3 * i + 1], p.g) << "frac " << frac << " texel " << i;
        ASSERT_EQ(rgb[3 * i + 2], p.b) << "frac " << frac << " texel " << i;
      }
    }
  }
}

// With 0 fractional bits the conversion is the one format versions 1 to 6
// define: Y + round_q16(91881 (V - 128)), and so on.
TEST(SampleFrac, WholeSamplesConvertAsBefore) {
  auto round_q16 = [](int64_t a) { return static_cast<int32_t>((a + 32768) >> 16); };
  auto clamp8 = [](int32_t x) { return x < 0 ? 0 : x > 255 ? 255 : x; };
  for (int y = 0; y < 256; y += 5)
    for (int u = 0; u < 256; u += 3)
      for (int v = 0; v < 256; v += 7) {
        const Rgb8 p = YuvToRgb(ColourSpace::kYCbCr601, y, u, v);
        ASSERT_EQ(p.r, clamp8(y + round_q16(91881LL * (v - 128))));
        ASSERT_EQ(p.g, clamp8(y + round_q16(-22554LL * (u - 128) - 46802LL * (v - 128))));
        ASSERT_EQ(p.b, clamp8(y + round_q16(116130LL * (u - 128))));
      }
}

// RGB -> YCbCr -> RGB loses less with more fractional bits; with 3 it is exact
// on all but a colour or two of a dense grid (whole samples round twice and
// miss thousands).
TEST(SampleFrac, ColourRoundTripIsNearlyExactWithThreeBits) {
  int errors[kMaxSampleFrac + 1] = {};
  for (int frac = 0; frac <= kMaxSampleFrac; ++frac)
    for (int r = 0; r < 256; r += 3)
      for (int g = 0; g < 256; g += 5)
        for (int b = 0; b < 256; b += 2) {
          const Yuv q = RgbToYuv(ColourSpace::kYCbCr601, r, g, b, frac);
          const Rgb8 p = YuvToRgb(ColourSpace::kYCbCr601, q.y, q.u, q.v, frac);
          errors[frac] += (p.r != r) + (p.g != g) + (p.b != b);
        }
  EXPECT_GT(errors[0], 1000);
  EXPECT_LT(errors[1], errors[0]);
  EXPECT_LE(errors[3], 2);
  EXPECT_LE(errors[4], 2);
}

// The point of it: at high rates the rounding of whole samples was most of
// the error. Asserted: over +0.3 dB at 2 and 4 bpp, within 0.1 dB at 0.1 bpp.
TEST(SampleFrac, BetterRgbAtEqualBytes) {
  const Shape4D shape{{2, 1, 96, 112}};
  const std::vector<uint8_t> rgb = TestRgb(shape, 3);
  for (double bpp : {2.0, 4.0}) {
    const double whole = CodedRgbPsnr(rgb, shape, 0, bpp);
    const double frac3 = CodedRgbPsnr(rgb, shape, 3, bpp);
    EXPECT_GT(frac3, whole + 0.3) << bpp << " bpp";
  }
  EXPECT_GT(CodedRgbPsnr(rgb, shape, 3, 0.1), CodedRgbPsnr(rgb, shape, 0, 0.1) - 0.1);
}

// Every prefix of a fractional stream still decodes, and quality grows with bytes.
TEST(SampleFrac, PrefixesDecodeAndImprove) {
  const Shape4D shape{{2, 1, 40, 48}};
  const std::vector<uint8_t> rgb = TestRgb(shape, 8);
  const Block block =
      BlockFromRgb(rgb.data(), shape, ColourSpace::kYCbCr601, ChromaFormat::k420, 4);
  EncodeSettings s;
  s.frac_bits_97 = 6;
  s.rate_value = 3.0;
  auto enc = EncodeBlock(block, nullptr, s);
  ASSERT_TRUE(enc.ok()) << enc.status().ToString();
  double last = 0;
  for (uint64_t bytes :
       {uint64_t{1}, uint64_t{40}, uint64_t{200}, uint64_t{800}, enc->total_bytes()}) {
    DecodeBudget budget;
    budget.max_bytes = bytes;
    auto dec = DecodeBlock(*enc, budget, SerialRunner);
    ASSERT_TRUE(dec.ok());
    for (const Plane4D& p : dec->channels)
      for (int32_t v : p.samples) ASSERT_TRUE(v >= 0 && v <= 255 << 4) << v;
    std::vector<uint8_t> out(rgb.size());
    BlockToRgb(*dec, out.data());
    const double psnr = RgbPsnr(rgb, out);
    EXPECT_GE(psnr, last - 0.05) << bytes << " bytes";
    last = psnr;
  }
  EXPECT_GT(last, 30);
}

// Block file version 6 carries the fractional bits; bad values are refused.
TEST(SampleFrac, BlockFileVersion6) {
  const Shape4D shape{{2, 2, 12, 10}};
  const std::vector<uint8_t> rgb = TestRgb(shape, 4);
  EncodeSettings s;
  s.rate_value = 2.0;
  auto enc = EncodeBlock(
      BlockFromRgb(rgb.data(), shape, ColourSpace::kYCbCr601, ChromaFormat::k444, 3), nullptr, s);
  ASSERT_TRUE(enc.ok());
  const std::vector<uint8_t> file = WriteBlockFile(*enc);
  ASSERT_EQ(file[4], 6);
  ASSERT_EQ(file[9], 5);   // frac_bits
  ASSERT_EQ(file[10], 3);  // sample_frac
  auto parsed = ReadBlockFile(file.data(), file.size());
  ASSERT_TRUE(parsed.ok()) << parsed.status().ToString();
  EXPECT_EQ(parsed->params.sample_frac, 3);
  EXPECT_EQ(WriteBlockFile(*parsed), file);
  std::vector<uint8_t> bad = file;
  bad[10] = 5;  // above kMaxSampleFrac and frac_bits
  EXPECT_EQ(ReadBlockFile(bad.data(), bad.size()).status().code(), StatusCode::kCorrupt);
  bad = file;
  bad[7] = 1;  // RCT
  EXPECT_EQ(ReadBlockFile(bad.data(), bad.size()).status().code(), StatusCode::kCorrupt);
  bad = file;
  bad[4] = kBlockFileVersion + 1;
  EXPECT_EQ(ReadBlockFile(bad.data(), bad.size()).status().code(), StatusCode::kUnsupported);
  // Whole samples still write version 5.
  auto whole = EncodeBlock(
      BlockFromRgb(rgb.data(), shape, ColourSpace::kYCbCr601, ChromaFormat::k444, 0), nullptr, s);
  ASSERT_TRUE(whole.ok());
  EXPECT_EQ(WriteBlockFile(*whole)[4], 5);
}

// Coder 4 (format version 8) writes block file version 7; a file that says
// coder 4 in an older version is refused with the version it needs.
TEST(SampleFrac, BlockFileVersion7CarriesCoder4) {
  const Shape4D shape{{2, 2, 12, 10}};
  const std::vector<uint8_t> rgb = TestRgb(shape, 4);
  EncodeSettings s;
  s.rate_value = 2.0;
  s.coder = EntropyCoder::kQuadtree;
  auto enc = EncodeBlock(
      BlockFromRgb(rgb.data(), shape, ColourSpace::kYCbCr601, ChromaFormat::k444, 3), nullptr, s);
  ASSERT_TRUE(enc.ok());
  const std::vector<uint8_t> file = WriteBlockFile(*enc);
  ASSERT_EQ(file[4], 7);
  ASSERT_EQ(file[6], 4);  // coder
  auto parsed = ReadBlockFile(file.data(), file.size());
  ASSERT_TRUE(parsed.ok()) << parsed.status().ToString();
  EXPECT_EQ(parsed->params.coder, EntropyCoder::kQuadtree);
  EXPECT_EQ(WriteBlockFile(*parsed), file);
  std::vector<uint8_t> bad = file;
  bad[4] = 6;
  const Status old = ReadBlockFile(bad.data(), bad.size()).status();
  EXPECT_EQ(old.code(), StatusCode::kCorrupt);
  EXPECT_NE(old.message().find("needs version 7"), std::string::npos) << old.ToString();
  bad = file;
  bad[6] = 5;  // no such coder
  EXPECT_EQ(ReadBlockFile(bad.data(), bad.size()).status().code(), StatusCode::kCorrupt);
}

// The encoder refuses what no stream can say, with a message.
TEST(SampleFrac, EncoderRefusesImpossibleSettings) {
  const Shape4D shape{{1, 1, 16, 16}};
  const std::vector<uint8_t> rgb = TestRgb(shape, 2);
  const Block frac3 =
      BlockFromRgb(rgb.data(), shape, ColourSpace::kYCbCr601, ChromaFormat::k444, 3);
  EncodeSettings s;
  s.frac_bits_97 = 2;  // fewer transform bits than sample bits
  EXPECT_EQ(EncodeBlock(frac3, nullptr, s).status().code(), StatusCode::kInvalidArgument);
  s = EncodeSettings{};
  s.kernel = WaveletKernel::kLeGall53;
  EXPECT_EQ(EncodeBlock(frac3, nullptr, s).status().code(), StatusCode::kInvalidArgument);
  s = EncodeSettings{};
  s.weights = BandWeights::kAxisBands;
  const Status axis = EncodeBlock(frac3, nullptr, s).status();
  EXPECT_EQ(axis.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(axis.message().find("own-band"), std::string::npos) << axis.ToString();
  // RCT blocks are whole whatever is asked for.
  EXPECT_EQ(BlockFromRgb(rgb.data(), shape, ColourSpace::kRct, ChromaFormat::k444, 3).sample_frac,
            0);
}

}  // namespace
}  // namespace fvv
