// Block coding API: rate targets, masks, parameter checks, and the block file
// syntax under corrupt, truncated and random input.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <random>
#include <thread>

#include "codec/base/large_buffer.h"
#include "codec/base/thread_pool.h"
#include "codec/block_codec.h"
#include "codec/block_syntax.h"
#include "tests/test_blocks.h"

namespace fvv {
namespace {

using ::fvv::testing::HashBlock;
using ::fvv::testing::RandomBlock;
using ::fvv::testing::SmoothBlock;

double WeightedPsnr(const Block& a, const Block& b, const UsedMask* mask) {
  const double w[3] = {1.0, 1.0861, 0.8252};
  double s = 0;
  for (int c = 0; c < 3; ++c) s += w[c] * ChannelMse(a.channels[c], b.channels[c], mask);
  return PsnrFromMse(s / (w[0] + w[1] + w[2]));
}

TEST(RateControl, ByteAndBppTargetsAreMetAndQualityGrowsWithRate) {
  const Shape4D shape{{2, 4, 32, 48}};
  const Block block = SmoothBlock(shape, ColourSpace::kYCbCr601, 1);
  double last_psnr = 0;
  for (double bpp : {0.05, 0.1, 0.25, 0.5, 1.0}) {
    EncodeSettings s;
    s.rate_value = bpp;
    auto enc = EncodeBlock(block, nullptr, s);
    ASSERT_TRUE(enc.ok());
    const uint64_t budget = static_cast<uint64_t>(std::ceil(bpp * shape.count() / 8));
    EXPECT_LE(enc->total_bytes(), budget);
    EXPECT_GE(enc->total_bytes(), budget * 95 / 100) << "rate control left bytes unused";
    auto dec = DecodeBlock(*enc, DecodeBudget{}, SerialRunner);
    ASSERT_TRUE(dec.ok());
    const double psnr = WeightedPsnr(block, *dec, nullptr);
    EXPECT_GT(psnr, last_psnr) << "at " << bpp << " bpp";
    last_psnr = psnr;
  }
  EncodeSettings s;
  s.rate_mode = RateMode::kTotalBytes;
  s.rate_value = 1234;
  auto enc = EncodeBlock(block, nullptr, s);
  ASSERT_TRUE(enc.ok());
  EXPECT_LE(enc->total_bytes(), 1234u);
  EXPECT_GE(enc->total_bytes(), 1200u);
}

TEST(RateControl, PsnrTargetIsReachedWithoutLargeOvershoot) {
  const Shape4D shape{{2, 2, 40, 40}};
  const Block block = SmoothBlock(shape, ColourSpace::kYCbCr601, 2);
  for (double target : {30.0, 38.0, 45.0}) {
    EncodeSettings s;
    s.rate_mode = RateMode::kPsnr;
    s.rate_value = target;
    auto enc = EncodeBlock(block, nullptr, s);
    ASSERT_TRUE(enc.ok());
    auto dec = DecodeBlock(*enc, DecodeBudget{}, SerialRunner);
    const double psnr = WeightedPsnr(block, *dec, nullptr);
    EXPECT_GE(psnr, target);
    EXPECT_LT(psnr, target + 2.0);
  }
}

// A PSNR target over fewer texels than the mask codes (what the cameras saw,
// of what a player of a stream without masks may show): reached over those,
// with fewer bytes than the same target over the whole mask.
TEST(RateControl, PsnrTargetCountsItsOwnTexels) {
  const Shape4D shape{{2, 2, 40, 40}};
  Block block = SmoothBlock(shape, ColourSpace::kYCbCr601, 9);
  UsedMask coded(shape.count(), 1), counted(shape.count(), 0);
  std::mt19937 rng(3);
  for (size_t i = 0; i < counted.size(); ++i) {
    counted[i] = (i % 40) < 20;
    if (!counted[i]) block.channels[0].samples[i] = static_cast<int32_t>(rng() % 256);
  }
  EncodeSettings s;
  s.rate_mode = RateMode::kPsnr;
  s.rate_value = 34;
  auto whole = EncodeBlock(block, &coded, s);
  s.psnr_mask = &counted;
  auto part = EncodeBlock(block, &coded, s);
  ASSERT_TRUE(whole.ok() && part.ok());
  const double over_part = WeightedPsnr(block, *DecodeBlock(*part, {}, SerialRunner), &counted);
  EXPECT_GE(over_part, 34.0);
  EXPECT_LT(over_part, 36.0);
  EXPECT_GE(WeightedPsnr(block, *DecodeBlock(*whole, {}, SerialRunner), &coded), 34.0);
  EXPECT_LT(part->total_bytes(), whole->total_bytes());
  UsedMask wrong(3, 1);
  s.psnr_mask = &wrong;
  EXPECT_FALSE(EncodeBlock(block, &coded, s).ok());
}

TEST(RateControl, ChromaGetsFewerBytesThanLuma) {
  const Block block = SmoothBlock(Shape4D{{1, 1, 64, 64}}, ColourSpace::kYCbCr601, 5);
  Block grey_chroma = block;
  for (int c = 1; c < 3; ++c)
    for (int32_t& v : grey_chroma.channels[c].samples) v = 128 + (v - 128) / 8;
  EncodeSettings s;
  s.rate_value = 1.0;
  EncodeReport report;
  ASSERT_TRUE(EncodeBlock(grey_chroma, nullptr, s, &report).ok());
  EXPECT_GT(report.channel_bytes[0], report.channel_bytes[1] + report.channel_bytes[2]);
}

TEST(Masks, UnusedTexelsCostLittleAndUsedOnesAreCodedWell) {
  const Shape4D shape{{2, 2, 48, 48}};
  Block block = SmoothBlock(shape, ColourSpace::kYCbCr601, 3);
  UsedMask mask(shape.count(), 0);
  std::mt19937 rng(5);
  for (size_t i = 0; i < mask.size(); ++i) {
    const uint32_t x = i % 48, y = (i / 48) % 48;
    mask[i] = (x - 24.0) * (x - 24.0) + (y - 24.0) * (y - 24.0) < 300;
    if (!mask[i])
      block.channels[0].samples[i] = static_cast<int32_t>(rng() % 256);  // junk no camera saw
  }
  EncodeSettings s;
  s.rate_value = 0.5;
  auto with_mask = EncodeBlock(block, &mask, s);
  auto without = EncodeBlock(block, nullptr, s);
  ASSERT_TRUE(with_mask.ok() && without.ok());
  const double psnr_mask = WeightedPsnr(block, *DecodeBlock(*with_mask, {}, SerialRunner), &mask);
  const double psnr_plain = WeightedPsnr(block, *DecodeBlock(*without, {}, SerialRunner), &mask);
  EXPECT_GT(psnr_mask, psnr_plain + 3.0) << "filling should stop the junk from costing bits";
}

// The fill is what decides how many bits the edges of a mask cost: at equal
// bytes, the bilinear pull beats the parent pull, and the sparse fill beats
// both, on textured content seen through an irregular mask.
TEST(Masks, SmootherFillsGiveMoreQualityAtEqualBytes) {
  const Shape4D shape{{4, 1, 96, 96}};
  Block block = SmoothBlock(shape, ColourSpace::kYCbCr601, 7);
  UsedMask mask(shape.count(), 0);
  std::mt19937 rng(9);
  for (int blob = 0; blob < 10; ++blob) {
    const double cx = rng() % 96, cy = rng() % 96, r2 = 40 + rng() % 160;
    for (size_t i = 0; i < mask.size(); ++i) {
      const double x = double(i % 96), y = double((i / 96) % 96);
      if ((x - cx) * (x - cx) + (y - cy) * (y - cy) < r2) mask[i] = 1;
    }
  }
  auto psnr_with = [&](const FillOptions& fill) {
    EncodeSettings s;
    s.rate_value = 0.25;
    s.fill = fill;
    auto enc = EncodeBlock(block, &mask, s);
    EXPECT_TRUE(enc.ok());
    EXPECT_LE(enc->total_bytes(), uint64_t(0.25 * shape.count() / 8) + 1);
    return WeightedPsnr(block, *DecodeBlock(*enc, {}, SerialRunner), &mask);
  };
  const double parent = psnr_with({FillPull::kParent, 0});
  const double bilinear = psnr_with({FillPull::kBilinear, 0});
  const double sparse = psnr_with(FillOptions{});
  EXPECT_GT(bilinear, parent + 0.5);
  EXPECT_GT(sparse, bilinear + 0.1);
}

TEST(Params, BadSettingsAndShapesAreRejected) {
  const Block block = SmoothBlock(Shape4D{{1, 1, 8, 8}}, ColourSpace::kYCbCr601, 1);
  EncodeSettings s;
  s.rate_mode = RateMode::kLossless;  // with 9/7 and BT.601: not lossless
  EXPECT_EQ(EncodeBlock(block, nullptr, s).status().code(), StatusCode::kInvalidArgument);
  s.rate_mode = RateMode::kBitsPerSample;
  s.rate_value = -1;
  EXPECT_EQ(EncodeBlock(block, nullptr, s).status().code(), StatusCode::kInvalidArgument);
  s.rate_value = 1;
  UsedMask short_mask(10, 1);
  EXPECT_EQ(EncodeBlock(block, &short_mask, s).status().code(), StatusCode::kInvalidArgument);
  for (int frac : {kMinFracBits97 - 1, kMaxFracBits97 + 1}) {
    s.frac_bits_97 = frac;
    const Status st = EncodeBlock(block, nullptr, s).status();
    EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
    EXPECT_NE(st.message().find("precision"), std::string::npos) << st.message();
  }
  BlockParams p;
  p.shape.n = {1, 1, 70000, 1};
  EXPECT_EQ(ValidateParams(p).code(), StatusCode::kLimitExceeded);
  p.shape.n = {1, 1, 65535, 65535};
  EXPECT_EQ(ValidateParams(p).code(), StatusCode::kLimitExceeded);
  // Sample precision: 2..6 for the 9/7, 0 for the reversible kernels.
  p.shape.n = {1, 1, 8, 8};
  for (int frac : {0, 1, 7, 255}) {
    p.frac_bits = static_cast<uint8_t>(frac);
    EXPECT_EQ(ValidateParams(p).code(), StatusCode::kCorrupt) << frac;
  }
  p.frac_bits = kMaxFracBits97;
  EXPECT_TRUE(ValidateParams(p).ok());
  p.kernel = WaveletKernel::kLeGall53;
  EXPECT_EQ(ValidateParams(p).code(), StatusCode::kCorrupt);
  p.frac_bits = 0;
  EXPECT_TRUE(ValidateParams(p).ok());
}

double RgbPsnrAt(const Block& block, double bpp, int frac_bits_97) {
  EncodeSettings s;
  s.rate_value = bpp;
  s.frac_bits_97 = frac_bits_97;
  auto enc = EncodeBlock(block, nullptr, s);
  EXPECT_TRUE(enc.ok()) << enc.status().ToString();
  EXPECT_EQ(enc->params.frac_bits, frac_bits_97);
  auto dec = DecodeBlock(*enc, DecodeBudget{}, SerialRunner);
  EXPECT_TRUE(dec.ok());
  double mse = 0;
  for (int c = 0; c < 3; ++c) mse += ChannelMse(block.channels[c], dec->channels[c], nullptr) / 3;
  return PsnrFromMse(mse);
}

// The rounding of the 9/7's lifting steps at 2 fractional bits costs quality
// at high rates (why format version 3 added the precision field); at low
// rates the quantiser dominates and the precision hardly matters.
TEST(Precision, MoreFractionalBitsGiveMoreQualityAtHighRates) {
  const Block block = SmoothBlock(Shape4D{{4, 2, 48, 48}}, ColourSpace::kYCbCr601, 11);
  const double high2 = RgbPsnrAt(block, 3.0, kFracBits97Legacy);
  const double high5 = RgbPsnrAt(block, 3.0, kFracBits97);
  EXPECT_GT(high5, high2 + 0.3) << high2 << " -> " << high5;
  const double low2 = RgbPsnrAt(block, 0.1, kFracBits97Legacy);
  const double low5 = RgbPsnrAt(block, 0.1, kFracBits97);
  EXPECT_GT(low5, low2 - 0.1) << low2 << " -> " << low5;
}

// Full-scale content at the largest precision: constant extremes (the low
// band's gain) and a 4D checkerboard (the detail bands') keep their values
// through the transform and quantisation, with every axis split.
TEST(Precision, FullScaleContentSurvivesTheLargestPrecision) {
  const Shape4D shape{{4, 4, 64, 64}};
  for (int pattern = 0; pattern < 2; ++pattern) {
    Block block;
    block.colour = ColourSpace::kYCbCr601;
    for (int c = 0; c < 3; ++c) {
      block.channels[c] = Plane4D(shape);
      size_t i = 0;
      for (uint32_t t = 0; t < shape.n[0]; ++t)
        for (uint32_t k = 0; k < shape.n[1]; ++k)
          for (uint32_t y = 0; y < shape.n[2]; ++y)
            for (uint32_t x = 0; x < shape.n[3]; ++x, ++i) {
              const bool odd = ((t + k + y + x) & 1) != 0;
              block.channels[c].samples[i] = pattern == 0 ? (c == 0 ? 255 : 0) : (odd ? 255 : 0);
            }
    }
    EXPECT_GT(RgbPsnrAt(block, 12.0, kMaxFracBits97), 45.0) << "pattern " << pattern;
  }
}

// Per-axis weights unless asked: the block file versions of each coder.
std::vector<uint8_t> SmallBlockFile(EntropyCoder coder,
                                    BandWeights weights = BandWeights::kAxisBands) {
  EncodeSettings s;
  s.coder = coder;
  s.weights = weights;
  s.rate_value = 2.0;
  auto enc =
      EncodeBlock(SmoothBlock(Shape4D{{2, 2, 12, 10}}, ColourSpace::kYCbCr601, 4), nullptr, s);
  return WriteBlockFile(*enc);
}

TEST(BlockFile, RoundTripsExactly) {
  const std::vector<uint8_t> file = SmallBlockFile(EntropyCoder::kArith);
  auto parsed = ReadBlockFile(file.data(), file.size());
  ASSERT_TRUE(parsed.ok()) << parsed.status().ToString();
  EXPECT_EQ(WriteBlockFile(*parsed), file);
}

TEST(BlockFile, HeaderErrorsAreNamed) {
  std::vector<uint8_t> file = SmallBlockFile(EntropyCoder::kArith);
  std::vector<uint8_t> bad = file;
  bad[0] = 'x';
  EXPECT_EQ(ReadBlockFile(bad.data(), bad.size()).status().code(), StatusCode::kCorrupt);
  bad = file;
  bad[4] = 9;  // version
  EXPECT_EQ(ReadBlockFile(bad.data(), bad.size()).status().code(), StatusCode::kUnsupported);
  bad = file;
  bad[5] = 7;  // kernel
  EXPECT_EQ(ReadBlockFile(bad.data(), bad.size()).status().code(), StatusCode::kCorrupt);
  bad = file;
  bad[9 + 8] = 0xFF;  // height -> huge
  bad[9 + 10] = 0x7F;
  EXPECT_EQ(ReadBlockFile(bad.data(), bad.size()).status().code(), StatusCode::kLimitExceeded);
  bad = file;
  bad.push_back(0);
  EXPECT_EQ(ReadBlockFile(bad.data(), bad.size()).status().code(), StatusCode::kCorrupt);
}

// Coder 2 needs block file version 3 and coder 3 version 4; versions 1 and 2
// name coders 0 and 1 only, and coder 4 does not exist.
TEST(BlockFile, EachCoderHasItsFirstVersion) {
  for (const auto& [coder, version] : {std::pair{EntropyCoder::kNeighbourContexts, 3},
                                       std::pair{EntropyCoder::kSetSignContexts, 4}}) {
    const std::vector<uint8_t> file = SmallBlockFile(coder);
    ASSERT_EQ(file[4], version);
    EXPECT_EQ(file[6], static_cast<uint8_t>(coder));  // after magic, version and kernel
    auto parsed = ReadBlockFile(file.data(), file.size());
    ASSERT_TRUE(parsed.ok()) << parsed.status().ToString();
    EXPECT_EQ(parsed->params.coder, coder);
    EXPECT_EQ(WriteBlockFile(*parsed), file);
    std::vector<uint8_t> bad = file;
    bad[4] = static_cast<uint8_t>(version - 1);
    auto old = ReadBlockFile(bad.data(), bad.size());
    EXPECT_EQ(old.status().code(), StatusCode::kCorrupt);
    EXPECT_NE(old.status().message().find("needs version " + std::to_string(version)),
              std::string::npos)
        << old.status().message();
    bad = file;
    bad[6] = 4;
    auto unknown = ReadBlockFile(bad.data(), bad.size());
    EXPECT_EQ(unknown.status().code(), StatusCode::kCorrupt);
    EXPECT_NE(unknown.status().message().find("entropy coder 4"), std::string::npos);
  }
  EXPECT_EQ(SmallBlockFile(EntropyCoder::kArith)[4], 2);  // precision 5, coder 1
}

// Version 5 weights by own bands, with any coder; the same bytes read as
// version 4 decode validly but differently (the weights are not in the
// payload: the version says them).
TEST(BlockFile, Version5HasOwnBandWeights) {
  for (EntropyCoder coder : {EntropyCoder::kArith, EntropyCoder::kSetSignContexts}) {
    const std::vector<uint8_t> file = SmallBlockFile(coder, BandWeights::kOwnBand);
    ASSERT_EQ(file[4], 5);
    auto parsed = ReadBlockFile(file.data(), file.size());
    ASSERT_TRUE(parsed.ok()) << parsed.status().ToString();
    EXPECT_EQ(parsed->params.weights, BandWeights::kOwnBand);
    EXPECT_EQ(WriteBlockFile(*parsed), file);
    std::vector<uint8_t> v4 = file;
    v4[4] = 4;
    auto as_v4 = ReadBlockFile(v4.data(), v4.size());
    ASSERT_TRUE(as_v4.ok()) << as_v4.status().ToString();
    EXPECT_EQ(as_v4->params.weights, BandWeights::kAxisBands);
    auto own = DecodeBlock(*parsed, DecodeBudget{}, SerialRunner);
    auto axis = DecodeBlock(*as_v4, DecodeBudget{}, SerialRunner);
    ASSERT_TRUE(own.ok() && axis.ok());
    EXPECT_NE(HashBlock(*own), HashBlock(*axis));
  }
}

// Every prefix and every single-byte change: a defined outcome, never a crash
// (run under ASan+UBSan in CI).
TEST(BlockFile, EveryPrefixAndByteFlipEndsInErrorOrValidDecode) {
  for (EntropyCoder coder :
       {EntropyCoder::kBinary, EntropyCoder::kArith, EntropyCoder::kNeighbourContexts,
        EntropyCoder::kSetSignContexts, EntropyCoder::kQuadtree}) {
    const std::vector<uint8_t> file =
        SmallBlockFile(coder, coder >= EntropyCoder::kSetSignContexts ? BandWeights::kOwnBand
                                                                      : BandWeights::kAxisBands);
    for (size_t n = 0; n < file.size(); ++n) {
      auto parsed = ReadBlockFile(file.data(), n);
      ASSERT_FALSE(parsed.ok()) << "prefix " << n << " parsed";
      EXPECT_EQ(parsed.status().code(), StatusCode::kTruncated) << parsed.status().ToString();
    }
    // A changed shape field can make the block thousands of times larger,
    // within the limits: each coder decodes one such block of up to 2M samples
    // (its short stream runs out early in it); larger ones, a second for the
    // inverse transform over zeros, are left to fuzz_block.
    constexpr uint64_t kMaxDecodedSamples = 2u << 20;
    int decoded = 0, large = 0;
    for (size_t i = 0; i < file.size(); ++i) {
      for (uint8_t flip : {0x01, 0x80, 0xFF}) {
        std::vector<uint8_t> bad = file;
        bad[i] ^= flip;
        auto parsed = ReadBlockFile(bad.data(), bad.size());
        if (!parsed.ok()) continue;
        const uint64_t samples = parsed->params.shape.count();
        if (samples > kMaxDecodedSamples) continue;
        auto dec = DecodeBlock(*parsed, DecodeBudget{}, SerialRunner);
        if (dec.ok()) ++decoded;
        if (samples > 100 * uint64_t(2 * 2 * 12 * 10)) {
          ++large;
          EXPECT_TRUE(dec.ok()) << "byte " << i << ": " << dec.status().ToString();
        }
      }
    }
    EXPECT_GT(decoded, 0);
    EXPECT_GT(large, 0);
  }
}

TEST(BlockFile, RandomBytesNeverCrash) {
  std::mt19937 rng(11);
  const std::vector<uint8_t> good = SmallBlockFile(EntropyCoder::kArith);
  for (int trial = 0; trial < 300; ++trial) {
    // A valid header with random streams exercises the SPIHT decoder; pure noise the parser.
    std::vector<uint8_t> data = trial % 2 ? good : std::vector<uint8_t>(rng() % 200);
    for (size_t i = trial % 2 ? 25 : 0; i < data.size(); ++i) data[i] = static_cast<uint8_t>(rng());
    auto parsed = ReadBlockFile(data.data(), data.size());
    if (parsed.ok()) (void)DecodeBlock(*parsed, DecodeBudget{}, SerialRunner);
  }
}

TEST(Decoder, RandomStreamsWithValidHeadersDecodeToClampedSamples) {
  std::mt19937 rng(12);
  // The 9/7 at the smallest, the default and the largest precision.
  const std::pair<WaveletKernel, int> kernels[] = {{WaveletKernel::kHaar, 0},
                                                   {WaveletKernel::kLeGall53, 0},
                                                   {WaveletKernel::kCdf97, kMinFracBits97},
                                                   {WaveletKernel::kCdf97, kFracBits97},
                                                   {WaveletKernel::kCdf97, kMaxFracBits97}};
  for (const auto& [k, frac] : kernels) {
    EncodedBlock enc;
    enc.params.shape.n = {3, 2, 9, 14};
    enc.params.kernel = k;
    enc.params.frac_bits = static_cast<uint8_t>(frac);
    for (ChannelStream& s : enc.channels) {
      s.planes = kMaxBitplanes;
      s.data.resize(3000);
      for (uint8_t& b : s.data) b = static_cast<uint8_t>(rng());
    }
    for (EntropyCoder coder :
         {EntropyCoder::kBinary, EntropyCoder::kArith, EntropyCoder::kQuadtree}) {
      enc.params.coder = coder;
      auto dec = DecodeBlock(enc, DecodeBudget{}, SerialRunner);
      ASSERT_TRUE(dec.ok());
      for (const Plane4D& p : dec->channels)
        for (int32_t v : p.samples) ASSERT_TRUE(v >= 0 && v <= 255);
    }
  }
}

// Two blocks (of different shapes, for the tests of state kept between
// decodes) encoded at `bpp`.
std::pair<StatusOr<EncodedBlock>, StatusOr<EncodedBlock>> EncodeTwo(const Block& a, const Block& b,
                                                                    double bpp) {
  EncodeSettings s;
  s.rate_value = bpp;
  return {EncodeBlock(a, nullptr, s), EncodeBlock(b, nullptr, s)};
}

// The SPIHT traversal keeps per-thread state that each traversal must leave
// clean, however it ends (a byte budget, a time budget, corrupt data, the end):
// decodes on one thread after each kind of ending equal decodes on a fresh
// thread. The blocks have different shapes, so a stale mark would land inside
// the next one.
TEST(Decoder, EveryWayADecodeEndsLeavesTheThreadClean) {
  // Not a structured binding: the thread's lambda below captures these.
  const auto encoded =
      EncodeTwo(RandomBlock(Shape4D{{2, 3, 20, 28}}, ColourSpace::kYCbCr601, 5),
                SmoothBlock(Shape4D{{3, 2, 17, 30}}, ColourSpace::kYCbCr601, 6), 2.0);
  const StatusOr<EncodedBlock>& ea = encoded.first;
  const StatusOr<EncodedBlock>& eb = encoded.second;
  ASSERT_TRUE(ea.ok() && eb.ok());
  uint64_t reference[2];
  std::thread([&] {
    reference[0] = HashBlock(DecodeBlock(*ea, DecodeBudget{}, SerialRunner).value());
    reference[1] = HashBlock(DecodeBlock(*eb, DecodeBudget{}, SerialRunner).value());
  }).join();
  EncodedBlock corrupt = *ea;
  for (ChannelStream& c : corrupt.channels)
    for (size_t i = c.data.size() / 3; i < c.data.size(); i += 7) c.data[i] ^= 0x5a;
  DecodeBudget cut;
  cut.max_bytes = ea->total_bytes() / 4;
  DecodeBudget late;
  late.max_ms = 1e-6;
  for (int end = 0; end < 4; ++end) {
    const EncodedBlock& first = end == 3 ? corrupt : *ea;
    const DecodeBudget& budget = end == 1 ? cut : end == 2 ? late : DecodeBudget{};
    const bool ok = DecodeBlock(first, budget, SerialRunner).ok();
    EXPECT_TRUE(ok || end >= 2) << "ending " << end;
    EXPECT_EQ(HashBlock(DecodeBlock(*eb, DecodeBudget{}, SerialRunner).value()), reference[1])
        << "after ending " << end;
    EXPECT_EQ(HashBlock(DecodeBlock(*ea, DecodeBudget{}, SerialRunner).value()), reference[0])
        << "after ending " << end;
  }
}

// Buffers recycled through a SamplePool (dirty, of other sizes) decode to the
// same samples as fresh ones; the pool keeps at most its limit.
TEST(Decoder, RecycledSampleBuffersGiveTheSameBlock) {
  const auto [ea, eb] =
      EncodeTwo(SmoothBlock(Shape4D{{2, 3, 20, 28}}, ColourSpace::kYCbCr601, 3),
                RandomBlock(Shape4D{{3, 2, 17, 9}}, ColourSpace::kYCbCr601, 4), 1.0);
  ASSERT_TRUE(ea.ok() && eb.ok());
  auto fresh_a = DecodeBlock(*ea, DecodeBudget{}, SerialRunner);
  auto fresh_b = DecodeBlock(*eb, DecodeBudget{}, SerialRunner);
  ASSERT_TRUE(fresh_a.ok() && fresh_b.ok());

  SamplePool pool;
  pool.SetLimit(3);
  // Dirty buffers, larger and smaller than a channel.
  for (size_t n : {10u, 5000u, 100000u, 7u}) pool.Give(std::vector<int32_t>(n, -12345));
  EXPECT_EQ(pool.pooled(), 3u);
  DecodeBudget budget;
  budget.sample_pool = &pool;
  for (int round = 0; round < 3; ++round) {
    auto da = DecodeBlock(*ea, budget, SerialRunner);
    ASSERT_TRUE(da.ok());
    EXPECT_EQ(HashBlock(*da), HashBlock(*fresh_a)) << "round " << round;
    for (Plane4D& p : da->channels) pool.Give(std::move(p.samples));
    auto db = DecodeBlock(*eb, budget, SerialRunner);
    ASSERT_TRUE(db.ok());
    EXPECT_EQ(HashBlock(*db), HashBlock(*fresh_b)) << "round " << round;
    for (Plane4D& p : db->channels) pool.Give(std::move(p.samples));
    EXPECT_LE(pool.pooled(), 3u);
  }
  pool.SetLimit(1);
  EXPECT_EQ(pool.pooled(), 1u);
  EXPECT_TRUE(pool.Take().empty());
  EXPECT_EQ(pool.pooled(), 0u);
}

// AssignLarge fills exactly like assign on every path: a fresh buffer large
// enough to be advised for huge pages (with a misaligned start), growth that
// keeps nothing of a dirty buffer, and shrinking that reuses the allocation.
TEST(LargeBuffer, AssignLargeFillsLikeAssign) {
  std::vector<int32_t> v;
  const size_t big = (size_t{9} << 20) / sizeof(int32_t) + 3;  // 9 MiB: four whole 2 MiB pages
  AssignLarge(&v, big, int32_t{-7});
  ASSERT_EQ(v.size(), big);
  EXPECT_EQ(std::count(v.begin(), v.end(), -7), static_cast<ptrdiff_t>(big));
  const int32_t* data = v.data();
  AssignLarge(&v, size_t{1000});
  ASSERT_EQ(v.size(), 1000u);
  EXPECT_EQ(v.data(), data) << "a smaller size reuses the buffer";
  EXPECT_EQ(std::count(v.begin(), v.end(), 0), 1000);
  std::vector<uint8_t> bytes(17, 0xAB);
  AssignLarge(&bytes, size_t{5} << 20);
  EXPECT_EQ(std::count(bytes.begin(), bytes.end(), 0), static_cast<ptrdiff_t>(5 << 20));
  // Advice on ranges without a whole huge page, or on nothing, is a no-op.
  int32_t small[4] = {1, 2, 3, 4};
  AdviseHugePages(small, sizeof(small));
  AdviseHugePages(nullptr, size_t{8} << 20);
  EXPECT_EQ(small[3], 4);
}

// A nested section opened by a task that ends early gets the pool's idle
// threads: the two nested tasks can only both finish if they run at the same
// time (each waits for the other), which a pool running nested calls inline
// never does.
TEST(ThreadPool, IdleThreadsJoinANestedSection) {
  ThreadPool pool(2);
  std::atomic<int> arrived{0};
  std::atomic<int> met{0};
  pool.Run(2, [&](uint32_t i) {
    if (i == 0) return;  // ends at once: its thread is free for the nested section
    pool.Run(2, [&](uint32_t) {
      arrived.fetch_add(1);
      const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(20);
      while (arrived.load() < 2 && std::chrono::steady_clock::now() < give_up)
        std::this_thread::yield();
      if (arrived.load() == 2) met.fetch_add(1);
    });
  });
  EXPECT_EQ(met.load(), 2) << "the nested tasks never ran side by side";
}

TEST(ThreadPool, RunsEveryTaskOnceIncludingNestedCalls) {
  ThreadPool pool(3);
  std::vector<std::atomic<int>> hits(200);
  pool.Run(20,
           [&](uint32_t i) { pool.Run(10, [&](uint32_t j) { hits[i * 10 + j].fetch_add(1); }); });
  for (auto& h : hits) EXPECT_EQ(h.load(), 1);
  // Many callers at once, each nesting two deep, over and over: tasks are
  // taken without the pool's lock, so races show as lost or repeated tasks or
  // a crash.
  constexpr int kRounds = 1000;
  std::vector<std::atomic<int>> deep(4 * 8 * 6);
  std::vector<std::thread> callers;
  for (uint32_t k = 0; k < 4; ++k)
    callers.emplace_back([&, k] {
      for (int round = 0; round < kRounds; ++round)
        pool.Run(8, [&](uint32_t i) {
          pool.Run(3, [&](uint32_t j) {
            pool.Run(2, [&](uint32_t m) { deep[(k * 8 + i) * 6 + j * 2 + m].fetch_add(1); });
          });
        });
    });
  for (std::thread& t : callers) t.join();
  for (auto& h : deep) EXPECT_EQ(h.load(), kRounds);
  ThreadPool decode_pool(2);
  const Block block = RandomBlock(Shape4D{{2, 3, 17, 21}}, ColourSpace::kRct, 8);
  EncodeSettings s;
  s.kernel = WaveletKernel::kLeGall53;
  s.rate_mode = RateMode::kLossless;
  auto serial = EncodeBlock(block, nullptr, s);
  s.runner = decode_pool.runner();
  auto parallel = EncodeBlock(block, nullptr, s);
  EXPECT_EQ(WriteBlockFile(*serial), WriteBlockFile(*parallel))
      << "threads must not change the stream";
  // Nor the decoded samples of a lossy 9/7 block, whose channels' inverse
  // transforms run beside the other channels' SPIHT decodes.
  const Block lossy_input = RandomBlock(Shape4D{{4, 2, 33, 40}}, ColourSpace::kYCbCr601, 9);
  EncodeSettings lossy;
  lossy.rate_value = 0.5;
  auto coded = EncodeBlock(lossy_input, nullptr, lossy);
  ASSERT_TRUE(coded.ok()) << coded.status().ToString();
  auto one = DecodeBlock(*coded, DecodeBudget{}, SerialRunner);
  auto two = DecodeBlock(*coded, DecodeBudget{}, decode_pool.runner());
  ASSERT_TRUE(one.ok() && two.ok());
  for (int c = 0; c < 3; ++c)
    EXPECT_EQ(one->channels[c].samples, two->channels[c].samples) << "channel " << c;
}

}  // namespace
}  // namespace fvv
