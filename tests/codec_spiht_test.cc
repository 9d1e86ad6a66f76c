// 4D SPIHT: tree structure, lossless round trips, embeddedness, budgets.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>

#include "codec/block_codec.h"
#include "codec/quadtree4d.h"
#include "codec/spiht4d.h"
#include "codec/thread_pool.h"
#include "tests/test_blocks.h"

namespace fvv {
namespace {

using ::fvv::testing::RandomBlock;
using ::fvv::testing::SmoothBlock;

const Shape4D kOddShapes[] = {Shape4D{{3, 5, 17, 33}}, Shape4D{{1, 1, 64, 64}},
                              Shape4D{{8, 8, 32, 32}}, Shape4D{{2, 7, 1, 9}},
                              Shape4D{{1, 1, 1, 1}},   Shape4D{{5, 1, 3, 1}}};

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
                      LosslessCase{WaveletKernel::kHaar, EntropyCoder::kArith2},
                      LosslessCase{WaveletKernel::kHaar, EntropyCoder::kArith3},
                      LosslessCase{WaveletKernel::kHaar, EntropyCoder::kArith4},
                      LosslessCase{WaveletKernel::kLeGall53, EntropyCoder::kBinary},
                      LosslessCase{WaveletKernel::kLeGall53, EntropyCoder::kArith},
                      LosslessCase{WaveletKernel::kLeGall53, EntropyCoder::kArith2},
                      LosslessCase{WaveletKernel::kLeGall53, EntropyCoder::kArith3},
                      LosslessCase{WaveletKernel::kLeGall53, EntropyCoder::kArith4}));

// A textured block whose frames are the same pattern moved a little (as a
// GOP's atlas textures are, where the tracked surface slides by a texel or so):
// edges of a coarse checker and a few sinusoids, plus noise.
Block MovingTextureBlock(const Shape4D& shape, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int32_t> noise(-1, 1);
  return testing::FunctionBlock(
      shape, ColourSpace::kYCbCr601, [&](int c, uint32_t t, uint32_t cam, uint32_t y, uint32_t x) {
        const double u = x + 0.4 * t + 3.0 * cam, w = y + 0.25 * t;
        const bool check = (int(u / 29) + int(w / 23)) % 2 != 0;
        const double v = 128 + (check ? 12 : -12) / (c + 1.0) + 20 * std::sin(0.05 * u + c) +
                         15 * std::cos(0.04 * w - 0.03 * u);
        return std::clamp<int32_t>(static_cast<int32_t>(v) + noise(rng), 0, 255);
      });
}

// PSNR of `block` coded at `bpp` with `coder`, of Y and of the three channels
// weighted as in RGB (what the rate allocation minimises); also checks that the
// stream read with the contexts of `other` decodes to something else.
struct CodedPsnr {
  double y = 0, weighted = 0;
};
CodedPsnr PsnrAtRate(const Block& block, EntropyCoder coder, double bpp, EntropyCoder other,
                     ThreadPool* pool, BandWeights weights = BandWeights::kOwnBand) {
  EncodeSettings s;
  s.coder = coder;
  s.weights = weights;
  s.rate_value = bpp;
  s.runner = pool->runner();
  s.prune_isolated = false;  // the coder alone: pruning helps both, the weaker more
  auto enc = EncodeBlock(block, nullptr, s);
  EXPECT_TRUE(enc.ok()) << enc.status().ToString();
  if (!enc.ok()) return {};
  EXPECT_EQ(enc->params.coder, coder);
  EXPECT_LE(enc->total_bytes(), uint64_t(std::ceil(bpp * block.shape().count() / 8)));
  auto dec = DecodeBlock(*enc, DecodeBudget{}, pool->runner());
  EXPECT_TRUE(dec.ok()) << dec.status().ToString();
  if (!dec.ok()) return {};
  EncodedBlock wrong = *enc;
  wrong.params.coder = other;
  auto misread = DecodeBlock(wrong, DecodeBudget{}, pool->runner());
  EXPECT_TRUE(misread.ok());
  if (misread.ok()) {
    EXPECT_NE(misread->channels[0].samples, dec->channels[0].samples);
  }
  double mse = 0, weight_sum = 0;
  for (int c = 0; c < 3; ++c) {
    mse += s.channel_weights[c] * ChannelMse(block.channels[c], dec->channels[c], nullptr);
    weight_sum += s.channel_weights[c];
  }
  return {PsnrFromMse(ChannelMse(block.channels[0], dec->channels[0], nullptr)),
          PsnrFromMse(mse / weight_sum)};
}

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
    const double arith = PsnrAtRate(block, EntropyCoder::kArith, bpp, EntropyCoder::kArith2, &pool,
                                    BandWeights::kAxisBands)
                             .y;
    const double arith2 = PsnrAtRate(block, EntropyCoder::kArith2, bpp, EntropyCoder::kArith, &pool,
                                     BandWeights::kAxisBands)
                              .y;
    EXPECT_GT(arith2, arith + 0.2) << "at " << bpp << " bpp";
  }
}

// The two blocks the coding comparisons below run on: an 8-frame moving
// texture and one larger still frame of it.
std::pair<Block, Block> MovingAndStillBlocks() {
  return {MovingTextureBlock(Shape4D{{8, 1, 256, 256}}, 5),
          MovingTextureBlock(Shape4D{{1, 1, 384, 384}}, 7)};
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
    const double arith2 =
        PsnrAtRate(*block, EntropyCoder::kArith2, bpp, EntropyCoder::kArith3, &pool).weighted;
    const double arith3 =
        PsnrAtRate(*block, EntropyCoder::kArith3, bpp, EntropyCoder::kArith2, &pool).weighted;
    EXPECT_GT(arith3, arith2 + 0.05) << block->shape().ToString() << " at " << bpp << " bpp";
  }
}

// Coder 4 (format version 8) against coder 3 on textures that fill the fine
// bands: quadtrees per band code them with fewer decisions than SPIHT's set
// tests. Weighted PSNR at equal bytes. Measured: still +0.28, +0.74, +1.50 and
// +0.65 dB at 0.1, 0.2, 0.3 and 1 bpp; moving +0.27, +0.91 and +0.59 dB at
// 0.05, 0.1 and 0.2 bpp. (On the demo's atlas textures, with their smooth
// fills, the two are within 0.02 dB: docs/encoder.md.)
TEST(Arith4, BetterAtEqualBytesThanArith3OnTextures) {
  ThreadPool pool(2);
  const auto [moving, still] = MovingAndStillBlocks();
  for (double bpp : {0.1, 0.2, 0.3, 1.0}) {
    const double arith3 =
        PsnrAtRate(still, EntropyCoder::kArith3, bpp, EntropyCoder::kArith4, &pool).weighted;
    const double arith4 =
        PsnrAtRate(still, EntropyCoder::kArith4, bpp, EntropyCoder::kArith3, &pool).weighted;
    EXPECT_GT(arith4, arith3 + 0.1) << "still, at " << bpp << " bpp";
  }
  for (double bpp : {0.05, 0.1, 0.2}) {
    const double arith3 =
        PsnrAtRate(moving, EntropyCoder::kArith3, bpp, EntropyCoder::kArith4, &pool).weighted;
    const double arith4 =
        PsnrAtRate(moving, EntropyCoder::kArith4, bpp, EntropyCoder::kArith3, &pool).weighted;
    EXPECT_GT(arith4, arith3 + 0.1) << "moving, at " << bpp << " bpp";
  }
}

// Coder 4's bands: every coefficient in exactly one band, each band's parent a
// level up with the same high-pass axes, each tree level's grid the one below
// halved, and one node at the top.
TEST(QuadtreeLayout, BandsPartitionTheBlockAndTreesHalve) {
  for (const Shape4D& shape :
       {kOddShapes[0], kOddShapes[1], kOddShapes[2], kOddShapes[3], kOddShapes[4], kOddShapes[5],
        Shape4D{{8, 1, 512, 512}}, Shape4D{{1, 1, 512, 768}}}) {
    const WaveletGeometry g(shape);
    const QuadtreeLayout layout(g);
    std::vector<int> covered(shape.count(), 0);
    size_t nodes = 0;
    for (const QuadtreeBand& b : layout.bands()) {
      std::array<uint32_t, kAxes> p;
      for (p[0] = 0; p[0] < b.n[0]; ++p[0])
        for (p[1] = 0; p[1] < b.n[1]; ++p[1])
          for (p[2] = 0; p[2] < b.n[2]; ++p[2])
            for (p[3] = 0; p[3] < b.n[3]; ++p[3]) ++covered[layout.Coefficient(b, p)];
      if (b.parent >= 0) {
        const QuadtreeBand& parent = layout.bands()[b.parent];
        EXPECT_EQ(parent.level, b.level + 1);
        EXPECT_EQ(parent.axes, b.axes);
      }
      ASSERT_EQ(b.dims.size(), size_t(b.top) + 1);
      EXPECT_EQ(b.dims[0], b.n);
      for (int k = 1; k <= b.top; ++k)
        for (int a = 0; a < kAxes; ++a) EXPECT_EQ(b.dims[k][a], (b.dims[k - 1][a] + 1) / 2);
      EXPECT_EQ(b.dims[b.top], (std::array<uint32_t, kAxes>{1, 1, 1, 1}));
      for (int k = 0; k <= b.top; ++k) {
        EXPECT_EQ(b.offset[k], nodes);
        nodes += size_t(b.dims[k][0]) * b.dims[k][1] * b.dims[k][2] * b.dims[k][3];
      }
    }
    EXPECT_EQ(nodes, layout.nodes());
    for (size_t i = 0; i < covered.size(); ++i)
      ASSERT_EQ(covered[i], 1) << shape.ToString() << " coefficient " << i;
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
    const double axis = PsnrAtRate(*block, EntropyCoder::kArith3, bpp, EntropyCoder::kArith2, &pool,
                                   BandWeights::kAxisBands)
                            .weighted;
    const double own =
        PsnrAtRate(*block, EntropyCoder::kArith3, bpp, EntropyCoder::kArith2, &pool).weighted;
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
    ::testing::Combine(
        ::testing::Values(WaveletKernel::kHaar, WaveletKernel::kLeGall53, WaveletKernel::kCdf97),
        ::testing::Values(EntropyCoder::kBinary, EntropyCoder::kArith, EntropyCoder::kArith2,
                          EntropyCoder::kArith3, EntropyCoder::kArith4)));

TEST(Embedded, EveryPrefixOfASmallStreamDecodes) {
  const Shape4D shape{{2, 2, 8, 12}};
  for (EntropyCoder coder : {EntropyCoder::kBinary, EntropyCoder::kArith, EntropyCoder::kArith2,
                             EntropyCoder::kArith3, EntropyCoder::kArith4}) {
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
                      PinnedDecode{kFracBits97, EntropyCoder::kArith2, kAxis, 0xfab51f3cb3aa7083ull,
                                   0xaefdc83fd44d6fdeull},
                      PinnedDecode{kFracBits97, EntropyCoder::kArith3, kAxis, 0x62dc3d1b0be03817ull,
                                   0x8606325f993a04eeull},
                      PinnedDecode{kFracBits97, EntropyCoder::kArith, kOwn, 0xf6654a815f27012full,
                                   0xcc775231cbac1526ull},
                      PinnedDecode{kFracBits97, EntropyCoder::kArith3, kOwn, 0x8b48ddf06e991203ull,
                                   0x61f784c10149a7fcull},
                      PinnedDecode{kFracBits97, EntropyCoder::kArith3, kOwn, 0xa68e2db331ebfc81ull,
                                   0x5730cf6b7812a4bfull, 3},
                      PinnedDecode{kFracBits97, EntropyCoder::kArith4, kOwn, 0xf6bfd95d18e268abull,
                                   0xb4df560a3fcfad7dull, 3}));

}  // namespace
}  // namespace fvv
