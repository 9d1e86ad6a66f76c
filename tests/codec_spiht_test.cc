// 4D SPIHT: tree structure, lossless round trips, embeddedness, budgets.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>

#include "codec/base/thread_pool.h"
#include "codec/block_codec.h"
#include "codec/spiht4d.h"
#include "tests/codec_coding_comparison.h"
#include "tests/test_blocks.h"

namespace fvv {
namespace {

using ::fvv::testing::CodedPsnr;
using ::fvv::testing::MovingAndStillBlocks;
using ::fvv::testing::MovingTextureBlock;
using ::fvv::testing::PsnrAtRate;
using ::fvv::testing::RandomBlock;
using ::fvv::testing::SmoothBlock;

using ::fvv::testing::kOddShapes;

TEST(SpihtTree, EveryCoefficientHasExactlyOneTreePath) {
  for (const Shape4D& shape : kOddShapes) {
    const WaveletGeometry g(shape);
    const SpihtTree tree(g);
    std::vector<int> visits(shape.count(), 0);
    std::vector<uint32_t> stack = tree.roots();
    for (uint32_t r : stack) ++visits[r];
    uint32_t children[kMaxChildren];
    while (!stack.empty()) {
      const uint32_t x = stack.back();
      stack.pop_back();
      const int n = tree.Children(x, children);
      ASSERT_LE(n, kMaxChildren);
      for (int i = 0; i < n; ++i) {
        ++visits[children[i]];
        stack.push_back(children[i]);
      }
    }
    for (size_t i = 0; i < visits.size(); ++i)
      ASSERT_EQ(visits[i], 1) << shape.ToString() << " index " << i;
  }
}

TEST(SpihtTree, GrandchildrenPredicateMatchesStructure) {
  for (const Shape4D& shape : kOddShapes) {
    const WaveletGeometry g(shape);
    const SpihtTree tree(g);
    uint32_t children[kMaxChildren], grand[kMaxChildren];
    for (uint32_t idx = 0; idx < shape.count(); ++idx) {
      const int n = tree.Children(idx, children);
      bool any = false;
      for (int i = 0; i < n && !any; ++i) any = tree.Children(children[i], grand) > 0;
      if (n > 0) {
        ASSERT_EQ(tree.HasGrandchildren(idx), any) << shape.ToString() << " index " << idx;
      }
    }
  }
}

// Coords divides by multiplication: compare it with the division it replaces,
// on every index of small shapes and on sampled indices (from both ends) of
// larger ones with odd and prime extents.
TEST(SpihtTree, CoordsAreTheIndexDecomposition) {
  std::vector<Shape4D> shapes(std::begin(kOddShapes), std::end(kOddShapes));
  shapes.push_back(Shape4D{{8, 8, 512, 512}});
  shapes.push_back(Shape4D{{3, 5, 1021, 1365}});
  shapes.push_back(Shape4D{{1, 255, 3, 9361}});
  for (const Shape4D& shape : shapes) {
    const SpihtTree tree{WaveletGeometry(shape)};
    const uint64_t count = shape.count();
    const uint64_t step = count <= (1u << 16) ? 1 : count / 65521;
    for (uint64_t i = 0; i < count; i += step) {
      for (uint64_t idx : {i, count - 1 - i}) {
        std::array<uint32_t, kAxes> p;
        tree.Coords(static_cast<uint32_t>(idx), &p);
        uint64_t q = idx;
        for (int a = kAxes - 1; a >= 0; --a) {
          ASSERT_EQ(p[a], q % shape.n[a]) << shape.ToString() << " index " << idx << " axis " << a;
          q /= shape.n[a];
        }
      }
    }
  }
}

// The shared tree is the tree of the shape asked for, reused while kept.
TEST(SpihtTree, SharedTreeIsTheShapesTree) {
  const WaveletGeometry a(Shape4D{{2, 3, 40, 24}}), b(Shape4D{{1, 1, 17, 33}});
  const auto ta = SharedSpihtTree(a), tb = SharedSpihtTree(b);
  EXPECT_EQ(ta->geometry().shape, a.shape);
  EXPECT_EQ(tb->geometry().shape, b.shape);
  EXPECT_EQ(SharedSpihtTree(a), ta);
  const SpihtTree fresh(a);
  EXPECT_EQ(ta->roots(), fresh.roots());
  uint32_t x[kMaxChildren], y[kMaxChildren];
  for (uint32_t idx = 0; idx < a.shape.count(); ++idx) {
    const int n = ta->Children(idx, x);
    ASSERT_EQ(n, fresh.Children(idx, y));
    ASSERT_TRUE(std::equal(x, x + n, y));
    ASSERT_EQ(ta->LevelClass(idx), fresh.LevelClass(idx));
  }
}

struct LosslessCase {
  WaveletKernel kernel;
  EntropyCoder coder;
};

class LosslessRoundTrip : public ::testing::TestWithParam<LosslessCase> {};

TEST_P(LosslessRoundTrip, FullRateIsExactOnOddShapes) {
  ThreadPool pool(2);
  for (const Shape4D& shape : kOddShapes) {
    for (int smooth = 0; smooth < 2; ++smooth) {
      const Block block = smooth ? SmoothBlock(shape, ColourSpace::kRct, 3)
                                 : RandomBlock(shape, ColourSpace::kRct, 4);
      EncodeSettings s;
      s.kernel = GetParam().kernel;
      s.coder = GetParam().coder;
      s.rate_mode = RateMode::kLossless;
      s.runner = pool.runner();
      auto enc = EncodeBlock(block, nullptr, s);
      ASSERT_TRUE(enc.ok()) << enc.status().ToString();
      DecodeReport report;
      auto dec = DecodeBlock(*enc, DecodeBudget{}, pool.runner(), &report);
      ASSERT_TRUE(dec.ok()) << dec.status().ToString();
      EXPECT_TRUE(report.complete);
      for (int c = 0; c < 3; ++c)
        ASSERT_EQ(dec->channels[c].samples, block.channels[c].samples)
            << shape.ToString() << " channel " << c << (smooth ? " smooth" : " random");
    }
  }
}

INSTANTIATE_TEST_SUITE_P(
    KernelsAndCoders, LosslessRoundTrip,
    ::testing::Values(LosslessCase{WaveletKernel::kHaar, EntropyCoder::kBinary},
                      LosslessCase{WaveletKernel::kHaar, EntropyCoder::kArith},
                      LosslessCase{WaveletKernel::kHaar, EntropyCoder::kNeighbourContexts},
                      LosslessCase{WaveletKernel::kHaar, EntropyCoder::kSetSignContexts},
                      LosslessCase{WaveletKernel::kHaar, EntropyCoder::kQuadtree},
                      LosslessCase{WaveletKernel::kLeGall53, EntropyCoder::kBinary},
                      LosslessCase{WaveletKernel::kLeGall53, EntropyCoder::kArith},
                      LosslessCase{WaveletKernel::kLeGall53, EntropyCoder::kNeighbourContexts},
                      LosslessCase{WaveletKernel::kLeGall53, EntropyCoder::kSetSignContexts},
                      LosslessCase{WaveletKernel::kLeGall53, EntropyCoder::kQuadtree}));

// Coder 2 (format version 4) against coder 1, and coder 3 (version 5) against
// coder 2: the same decisions in the same order with other contexts, so the
// rate control cuts both at the same budget; the newer coder decodes to a
// higher PSNR, and a stream read with the other coder's contexts decodes to
// something else. The block: the encoder's default GOP shape, 8 frames of one
// camera, whose frames resemble each other.
TEST(Arith2, BetterAtEqualBytesOnBlocksCorrelatedInTime) {
  ThreadPool pool(2);
  const Block block = MovingTextureBlock(Shape4D{{8, 1, 256, 256}}, 5);
  // Y PSNR, with the weights of format version 4. Measured: +0.36 dB at 0.1
  // bpp, +0.56 dB at 0.4 bpp. (With own-band weights, weighted PSNR: +0.14 and
  // +0.35 dB.)
  for (double bpp : {0.1, 0.4}) {
    const double arith =
        PsnrAtRate(block, EntropyCoder::kArith, bpp, EntropyCoder::kNeighbourContexts, &pool,
                   BandWeights::kAxisBands)
            .y;
    const double arith2 = PsnrAtRate(block, EntropyCoder::kNeighbourContexts, bpp,
                                     EntropyCoder::kArith, &pool, BandWeights::kAxisBands)
                              .y;
    EXPECT_GT(arith2, arith + 0.2) << "at " << bpp << " bpp";
  }
}

// Coder 3 gains in space as well as in time: on the moving texture and on one
// still frame of it. Weighted PSNR (a budget split differently across the
// channels can leave Y alone equal). Measured: moving +0.22, +0.26 and +0.17 dB
// at 0.05, 0.1 and 0.2 bpp; still +0.18, +0.09 and +0.11 dB at 0.1, 0.2 and
// 0.3 bpp.
TEST(Arith3, BetterAtEqualBytesThanArith2) {
  ThreadPool pool(2);
  const auto [moving, still] = MovingAndStillBlocks();
  for (const auto& [block, bpp] :
       {std::pair{&moving, 0.05}, std::pair{&moving, 0.1}, std::pair{&moving, 0.2},
        std::pair{&still, 0.1}, std::pair{&still, 0.2}, std::pair{&still, 0.3}}) {
    const double arith2 = PsnrAtRate(*block, EntropyCoder::kNeighbourContexts, bpp,
                                     EntropyCoder::kSetSignContexts, &pool)
                              .weighted;
    const double arith3 = PsnrAtRate(*block, EntropyCoder::kSetSignContexts, bpp,
                                     EntropyCoder::kNeighbourContexts, &pool)
                              .weighted;
    EXPECT_GT(arith3, arith2 + 0.05) << block->shape().ToString() << " at " << bpp << " bpp";
  }
}

// Own-band weights (format version 6) against the per-axis weights of versions
// 1 to 5, coder 3 both: the bitplanes of the moving texture and of a still
// frame are closer to rate-distortion order, so every rate gains. Weighted
// PSNR. Measured: moving +0.55, +0.51 and +0.62 dB at 0.05, 0.1 and 0.4 bpp;
// still +0.36, +0.17 and +0.63 dB at 0.1, 0.3 and 1 bpp.
TEST(OwnBandWeights, BetterAtEqualBytesThanAxisBands) {
  ThreadPool pool(2);
  const auto [moving, still] = MovingAndStillBlocks();
  for (const auto& [block, bpp] :
       {std::pair{&moving, 0.05}, std::pair{&moving, 0.1}, std::pair{&moving, 0.4},
        std::pair{&still, 0.1}, std::pair{&still, 0.3}, std::pair{&still, 1.0}}) {
    const double axis = PsnrAtRate(*block, EntropyCoder::kSetSignContexts, bpp,
                                   EntropyCoder::kNeighbourContexts, &pool, BandWeights::kAxisBands)
                            .weighted;
    const double own = PsnrAtRate(*block, EntropyCoder::kSetSignContexts, bpp,
                                  EntropyCoder::kNeighbourContexts, &pool)
                           .weighted;
    EXPECT_GT(own, axis + 0.1) << block->shape().ToString() << " at " << bpp << " bpp";
  }
}

EncodedBlock EncodeSmooth(const Shape4D& shape, WaveletKernel kernel, EntropyCoder coder,
                          double bpp, int frac_bits_97 = kFracBits97,
                          BandWeights weights = BandWeights::kOwnBand, int sample_frac = 0) {
  EncodeSettings s;
  s.kernel = kernel;
  s.weights = weights;
  s.frac_bits_97 = frac_bits_97;
  s.coder = coder;
  s.rate_value = bpp;
  s.prune_isolated = false;  // the streams the pinned hashes below were taken from
  Block block = SmoothBlock(shape, ColourSpace::kYCbCr601, 9);
  if (sample_frac > 0) {  // the same texture with fractional bits: x 2^p plus a pattern below 1
    for (Plane4D& p : block.channels)
      for (size_t i = 0; i < p.samples.size(); ++i)
        p.samples[i] =
            (p.samples[i] << sample_frac) + static_cast<int32_t>(i * 7 % (1 << sample_frac));
    block.sample_frac = static_cast<uint8_t>(sample_frac);
  }
  auto enc = EncodeBlock(block, nullptr, s);
  EXPECT_TRUE(enc.ok());
  return std::move(enc).value();
}

double DecodedYPsnr(const EncodedBlock& enc, uint64_t bytes, const Block& reference,
                    DecodeReport* report) {
  DecodeBudget budget;
  budget.max_bytes = bytes;
  auto dec = DecodeBlock(enc, budget, SerialRunner, report);
  EXPECT_TRUE(dec.ok());
  return PsnrFromMse(ChannelMse(reference.channels[0], dec->channels[0], nullptr));
}

class Embedded : public ::testing::TestWithParam<std::tuple<WaveletKernel, EntropyCoder>> {};

// SPIHT's refinement can move one coefficient's estimate away from its value,
// and with the biorthogonal kernels (5/3, 9/7) coefficient errors are not
// independent in the sample domain, so quality rises on average rather than
// decision by decision. Measured: Haar never drops; 5/3 and 9/7 drop by up to
// 0.25 dB across some refinement passes of tiny blocks. The bound below pins
// that; a larger drop is a regression.
constexpr double kDropToleranceDb = 0.3;
TEST_P(Embedded, QualityNeverDropsAsBytesAreAdded) {
  const Shape4D shape{{2, 3, 24, 40}};
  const Block ref = SmoothBlock(shape, ColourSpace::kYCbCr601, 9);
  const EncodedBlock enc =
      EncodeSmooth(shape, std::get<0>(GetParam()), std::get<1>(GetParam()), 2.0);
  double last = 0;
  for (uint64_t bytes = 16; bytes < 2 * enc.total_bytes(); bytes *= 2) {
    DecodeReport report;
    const double psnr = DecodedYPsnr(enc, std::min(bytes, enc.total_bytes()), ref, &report);
    EXPECT_LE(report.bytes_read, bytes);
    EXPECT_GE(psnr, last - kDropToleranceDb) << "at " << bytes << " bytes";
    last = std::max(last, psnr);
  }
  EXPECT_GT(last, 25.0);
  // Luma alone at each of its truncation points.
  EncodedBlock luma_only = enc;
  luma_only.channels[1].data.clear();
  luma_only.channels[2].data.clear();
  last = 0;
  for (const TruncationPoint& t : enc.channels[0].points) {
    DecodeReport report;
    const double psnr = DecodedYPsnr(luma_only, t.bytes, ref, &report);
    EXPECT_GE(psnr, last - kDropToleranceDb)
        << "at truncation point of plane " << int{t.plane} << " pass " << int{t.pass};
    last = std::max(last, psnr);
  }
}

INSTANTIATE_TEST_SUITE_P(
    KernelsAndCoders, Embedded,
    ::testing::Combine(::testing::Values(WaveletKernel::kHaar, WaveletKernel::kLeGall53,
                                         WaveletKernel::kCdf97),
                       ::testing::Values(EntropyCoder::kBinary, EntropyCoder::kArith,
                                         EntropyCoder::kNeighbourContexts,
                                         EntropyCoder::kSetSignContexts, EntropyCoder::kQuadtree)));

TEST(Embedded, EveryPrefixOfASmallStreamDecodes) {
  const Shape4D shape{{2, 2, 8, 12}};
  for (EntropyCoder coder :
       {EntropyCoder::kBinary, EntropyCoder::kArith, EntropyCoder::kNeighbourContexts,
        EntropyCoder::kSetSignContexts, EntropyCoder::kQuadtree}) {
    const EncodedBlock enc = EncodeSmooth(shape, WaveletKernel::kCdf97, coder, 3.0);
    const Block ref = SmoothBlock(shape, ColourSpace::kYCbCr601, 9);
    for (uint64_t bytes = 1; bytes <= enc.total_bytes(); ++bytes) {
      DecodeReport report;
      DecodedYPsnr(enc, bytes, ref, &report);
      ASSERT_LE(report.bytes_read, bytes);
    }
  }
}

TEST(Embedded, TruncationPointsAreOrderedAndWithinStream) {
  const EncodedBlock enc =
      EncodeSmooth(Shape4D{{2, 2, 32, 32}}, WaveletKernel::kCdf97, EntropyCoder::kArith, 1.0);
  for (const ChannelStream& s : enc.channels) {
    ASSERT_FALSE(s.points.empty());
    for (size_t i = 1; i < s.points.size(); ++i)
      EXPECT_GE(s.points[i].bytes, s.points[i - 1].bytes);
    EXPECT_LE(s.points.back().bytes, s.data.size());
  }
}

TEST(Decoder, TimeBudgetStopsEarlyAndSaysSo) {
  const EncodedBlock enc =
      EncodeSmooth(Shape4D{{4, 4, 64, 64}}, WaveletKernel::kCdf97, EntropyCoder::kArith, 2.0);
  DecodeBudget budget;
  budget.max_ms = 1e-6;  // already over when the first check comes
  DecodeReport report;
  auto dec = DecodeBlock(enc, budget, SerialRunner, &report);
  ASSERT_TRUE(dec.ok());
  EXPECT_TRUE(report.hit_deadline);
  EXPECT_FALSE(report.complete);
  EXPECT_LT(report.bytes_read, enc.total_bytes());
}

// Weighted PSNR and bytes of `block` coded at `bpp` (coder 3, own weights),
// pruning on or off.
std::pair<double, uint64_t> PrunedPsnr(const Block& block, double bpp, bool prune,
                                       ThreadPool* pool) {
  EncodeSettings s;
  s.rate_value = bpp;
  s.runner = pool->runner();
  s.prune_isolated = prune;
  Block decoded;
  EncodeReport report;
  report.decoded = &decoded;
  auto enc = EncodeBlock(block, nullptr, s, &report);
  EXPECT_TRUE(enc.ok()) << enc.status().ToString();
  if (!enc.ok()) return {0, 0};
  // The decode the encoder reports is what a decoder makes of the stream.
  auto dec = DecodeBlock(*enc, DecodeBudget{}, pool->runner());
  EXPECT_TRUE(dec.ok());
  if (!dec.ok()) return {0, 0};
  for (int c = 0; c < 3; ++c) EXPECT_EQ(dec->channels[c].samples, decoded.channels[c].samples);
  double mse = 0, weight_sum = 0;
  for (int c = 0; c < 3; ++c) {
    mse += s.channel_weights[c] * ChannelMse(block.channels[c], dec->channels[c], nullptr);
    weight_sum += s.channel_weights[c];
  }
  return {PsnrFromMse(mse / weight_sum), enc->total_bytes()};
}

// Pruning keeps a re-coded block only where it decodes with less error at the
// same bytes: never worse, within the budget, on smooth and textured blocks at
// low and high rates.
TEST(Prune, NeverWorseAtEqualBytes) {
  ThreadPool pool(2);
  const auto [moving, still] = MovingAndStillBlocks();
  const Block smooth = SmoothBlock(Shape4D{{2, 3, 40, 56}}, ColourSpace::kYCbCr601, 4);
  for (const Block* block : {&moving, &still, &smooth}) {
    for (double bpp : {0.05, 0.3, 2.0}) {
      const auto [on, on_bytes] = PrunedPsnr(*block, bpp, true, &pool);
      const auto [off, off_bytes] = PrunedPsnr(*block, bpp, false, &pool);
      const uint64_t budget = uint64_t(std::ceil(bpp * block->shape().count() / 8));
      EXPECT_LE(on_bytes, budget);
      EXPECT_GE(on, off) << block->shape().ToString() << " at " << bpp << " bpp";
    }
  }
}

// What it is for: smooth content with sparse isolated spikes (each a lone
// coefficient at the finest levels, costly to locate) at a rate that reaches
// the spikes' bitplane. Zeroing the spikes frees the bytes that locate them
// for the smooth content's clusters.
TEST(Prune, GainsWhereLoneCoefficientsCostMost) {
  ThreadPool pool(2);
  Block block = SmoothBlock(Shape4D{{1, 1, 256, 256}}, ColourSpace::kYCbCr601, 11);
  std::mt19937 rng(5);
  std::uniform_int_distribution<uint32_t> pos(0, 256 * 256 - 1);
  for (int k = 0; k < 400; ++k) {
    int32_t& s = block.channels[0].samples[pos(rng)];
    s = std::clamp(s + (k % 2 ? 24 : -24), 0, 255);
  }
  double gain = 0;
  for (double bpp : {0.1, 0.2, 0.4}) {
    const auto [on, on_bytes] = PrunedPsnr(block, bpp, true, &pool);
    const auto [off, off_bytes] = PrunedPsnr(block, bpp, false, &pool);
    EXPECT_GE(on, off) << bpp << " bpp";
    gain = std::max(gain, on - off);
  }
  EXPECT_GT(gain, 0.02);
}

// A fixed input coded with fixed settings: the stream and its decoding are pinned.
// A change here is a format change (see container/SPEC.md rules).
struct PinnedDecode {
  int frac_bits_97;
  EntropyCoder coder;
  BandWeights weights;
  uint64_t stream_hash, output_hash;
  int sample_frac = 0;  // format version 7 with 1..4
};

class DecoderPinned : public ::testing::TestWithParam<PinnedDecode> {};

TEST_P(DecoderPinned, OutputIsBitExact) {
  const EncodedBlock enc =
      EncodeSmooth(Shape4D{{3, 2, 19, 23}}, WaveletKernel::kCdf97, GetParam().coder, 1.0,
                   GetParam().frac_bits_97, GetParam().weights, GetParam().sample_frac);
  ASSERT_EQ(enc.params.frac_bits, GetParam().frac_bits_97);
  ASSERT_EQ(enc.params.weights, GetParam().weights);
  ASSERT_EQ(enc.params.sample_frac, GetParam().sample_frac);
  uint64_t stream_hash = 1469598103934665603ull;
  for (const ChannelStream& s : enc.channels)
    stream_hash = testing::Fnv1a(s.data.data(), s.data.size(), stream_hash);
  auto dec = DecodeBlock(enc, DecodeBudget{}, SerialRunner);
  ASSERT_TRUE(dec.ok());
  EXPECT_EQ(stream_hash, GetParam().stream_hash) << std::hex << stream_hash;
  EXPECT_EQ(testing::HashBlock(*dec), GetParam().output_hash)
      << std::hex << testing::HashBlock(*dec);
}

// f = 2: format versions 1 and 2 (and texr version 0 of version 3); f = 5: the
// default since format version 3; coder 2: the default of format version 4;
// coder 3: the default of format version 5; own-band weights (with coder 3 and
// coder 1): the default since format version 6; 3 fractional sample bits: the
// default since format version 7; coder 4: format version 8.
constexpr BandWeights kAxis = BandWeights::kAxisBands, kOwn = BandWeights::kOwnBand;
INSTANTIATE_TEST_SUITE_P(
    PrecisionAndCoder, DecoderPinned,
    ::testing::Values(PinnedDecode{kFracBits97Legacy, EntropyCoder::kArith, kAxis,
                                   0x287e15cac8b5f9ebull, 0xc935b295c6cd14e6ull},
                      PinnedDecode{kFracBits97, EntropyCoder::kArith, kAxis, 0x037d962b1e93695full,
                                   0xb763be1644f0c3a9ull},
                      PinnedDecode{kFracBits97, EntropyCoder::kNeighbourContexts, kAxis,
                                   0xfab51f3cb3aa7083ull, 0xaefdc83fd44d6fdeull},
                      PinnedDecode{kFracBits97, EntropyCoder::kSetSignContexts, kAxis,
                                   0x62dc3d1b0be03817ull, 0x8606325f993a04eeull},
                      PinnedDecode{kFracBits97, EntropyCoder::kArith, kOwn, 0xf6654a815f27012full,
                                   0xcc775231cbac1526ull},
                      PinnedDecode{kFracBits97, EntropyCoder::kSetSignContexts, kOwn,
                                   0x8b48ddf06e991203ull, 0x61f784c10149a7fcull},
                      PinnedDecode{kFracBits97, EntropyCoder::kSetSignContexts, kOwn,
                                   0xa68e2db331ebfc81ull, 0x5730cf6b7812a4bfull, 3},
                      PinnedDecode{kFracBits97, EntropyCoder::kQuadtree, kOwn,
                                   0xf6bfd95d18e268abull, 0xb4df560a3fcfad7dull, 3}));

}  // namespace
}  // namespace fvv
