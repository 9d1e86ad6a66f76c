// Coder 4, the quadtree per subband: its layout of bands and trees, and its
// coding against coder 3. (Round trips, every prefix, pinned decodes and
// budgets run for every coder in codec_spiht_test.cc.)
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <random>
#include <vector>

#include "codec/base/thread_pool.h"
#include "codec/quadtree4d.h"
#include "codec/quadtree4d_common.h"
#include "codec/spiht4d.h"
#include "tests/codec_coding_comparison.h"

namespace fvv {
namespace {

using ::fvv::testing::kOddShapes;
using ::fvv::testing::MovingAndStillBlocks;
using ::fvv::testing::PsnrAtRate;

// Coder 4 (format version 8) against coder 3 on textures that fill the fine
// bands: quadtrees per band code them with fewer decisions than SPIHT's set
// tests. Weighted PSNR at equal bytes. Measured: still +0.28, +0.74, +1.50 and
// +0.65 dB at 0.1, 0.2, 0.3 and 1 bpp; moving +0.27, +0.91 and +0.59 dB at
// 0.05, 0.1 and 0.2 bpp. (On the demo's atlas textures, with their smooth
// fills, the two are within 0.02 dB: docs/encoder.md.)
TEST(Quadtree, BetterAtEqualBytesThanSetSignContextsOnTextures) {
  ThreadPool pool(2);
  const auto [moving, still] = MovingAndStillBlocks();
  for (double bpp : {0.1, 0.2, 0.3, 1.0}) {
    const double arith3 =
        PsnrAtRate(still, EntropyCoder::kSetSignContexts, bpp, EntropyCoder::kQuadtree, &pool)
            .weighted;
    const double arith4 =
        PsnrAtRate(still, EntropyCoder::kQuadtree, bpp, EntropyCoder::kSetSignContexts, &pool)
            .weighted;
    EXPECT_GT(arith4, arith3 + 0.1) << "still, at " << bpp << " bpp";
  }
  for (double bpp : {0.05, 0.1, 0.2}) {
    const double arith3 =
        PsnrAtRate(moving, EntropyCoder::kSetSignContexts, bpp, EntropyCoder::kQuadtree, &pool)
            .weighted;
    const double arith4 =
        PsnrAtRate(moving, EntropyCoder::kQuadtree, bpp, EntropyCoder::kSetSignContexts, &pool)
            .weighted;
    EXPECT_GT(arith4, arith3 + 0.1) << "moving, at " << bpp << " bpp";
  }
}

// The SPIHT entry hands coder 4 to the quadtree coder: the same stream and the
// same decode either way, and the decode of a whole stream reproduces a
// different coefficient vector than that of a cut one.
TEST(Quadtree, SpihtEntryPointsCodeAndDecodeThroughTheQuadtree) {
  const WaveletGeometry g(Shape4D{{3, 2, 24, 40}});
  const auto tree = SharedSpihtTree(g);
  const SubbandQuantisers q(WaveletKernel::kLeGall53, 0, BandWeights::kOwnBand, g);
  std::mt19937 rng(11);
  std::uniform_int_distribution<int32_t> value(-300, 300);
  std::vector<int32_t> coefficients(tree->size());
  for (int32_t& c : coefficients) c = value(rng) / (1 + static_cast<int32_t>(rng() % 16));
  const SpihtEncoded direct = QuadtreeEncode(*tree, q, coefficients, UINT64_MAX);
  const SpihtEncoded entry =
      SpihtEncode(*tree, q, coefficients, EntropyCoder::kQuadtree, UINT64_MAX);
  ASSERT_FALSE(direct.data.empty());
  EXPECT_EQ(direct.data, entry.data);
  EXPECT_EQ(direct.planes, entry.planes);
  const SpihtEncoded spiht =
      SpihtEncode(*tree, q, coefficients, EntropyCoder::kSetSignContexts, UINT64_MAX);
  EXPECT_NE(spiht.data, direct.data);
  std::vector<int32_t> a, b, cut;
  const SpihtDecodeResult ra = QuadtreeDecode(*tree, q, direct.data.data(), direct.data.size(),
                                              direct.planes, SpihtDecodeLimits{}, &a);
  const SpihtDecodeResult rb =
      SpihtDecode(*tree, q, direct.data.data(), direct.data.size(), direct.planes,
                  EntropyCoder::kQuadtree, SpihtDecodeLimits{}, &b);
  EXPECT_TRUE(ra.complete);
  EXPECT_EQ(ra.bytes_used, rb.bytes_used);
  EXPECT_EQ(a, b);
  SpihtDecodeLimits half;
  half.max_bytes = direct.data.size() / 2;
  const SpihtDecodeResult rc =
      QuadtreeDecode(*tree, q, direct.data.data(), direct.data.size(), direct.planes, half, &cut);
  EXPECT_FALSE(rc.complete);
  EXPECT_LE(rc.bytes_used, half.max_bytes);
  EXPECT_NE(cut, a);
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

}  // namespace
}  // namespace fvv
