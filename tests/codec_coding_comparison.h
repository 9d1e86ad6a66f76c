// The coding comparisons' shared blocks and measure: a moving texture like a
// GOP's atlas textures, and the PSNR a coder reaches at a rate.
#ifndef FVV_TESTS_CODEC_CODING_COMPARISON_H_
#define FVV_TESTS_CODEC_CODING_COMPARISON_H_

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <utility>

#include "codec/base/thread_pool.h"
#include "codec/block_codec.h"
#include "tests/test_blocks.h"

namespace fvv::testing {

// A textured block whose frames are the same pattern moved a little (as a
// GOP's atlas textures are, where the tracked surface slides by a texel or so):
// edges of a coarse checker and a few sinusoids, plus noise.
inline Block MovingTextureBlock(const Shape4D& shape, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int32_t> noise(-1, 1);
  return FunctionBlock(
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
inline CodedPsnr PsnrAtRate(const Block& block, EntropyCoder coder, double bpp, EntropyCoder other,
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

// The two blocks the coding comparisons below run on: an 8-frame moving
// texture and one larger still frame of it.
inline std::pair<Block, Block> MovingAndStillBlocks() {
  return {MovingTextureBlock(Shape4D{{8, 1, 256, 256}}, 5),
          MovingTextureBlock(Shape4D{{1, 1, 384, 384}}, 7)};
}

}  // namespace fvv::testing

#endif  // FVV_TESTS_CODEC_CODING_COMPARISON_H_
