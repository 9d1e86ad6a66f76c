// Mask coder: lossless on structured and random masks, and safe on bad input.
#include <gtest/gtest.h>

#include <random>

#include "codec/mask_coder.h"

namespace fvv {
namespace {

Shape4D MakeShape(uint32_t t, uint32_t c, uint32_t h, uint32_t w) {
  Shape4D s;
  s.n = {t, c, h, w};
  return s;
}

std::vector<uint8_t> MovingDiscs(const Shape4D& s) {
  std::vector<uint8_t> m(s.count());
  for (uint32_t t = 0; t < s.frames(); ++t)
    for (uint32_t c = 0; c < s.cameras(); ++c)
      for (uint32_t y = 0; y < s.height(); ++y)
        for (uint32_t x = 0; x < s.width(); ++x) {
          const double dx = x - (s.width() * 0.4 + t + c), dy = y - s.height() * 0.5;
          m[s.Index(t, c, y, x)] = dx * dx + dy * dy < s.width() * s.width() * 0.08;
        }
  return m;
}

TEST(MaskCoder, RoundTripsExactly) {
  std::mt19937 rng(11);
  for (const Shape4D& s : {MakeShape(8, 3, 33, 47), MakeShape(1, 1, 1, 1), MakeShape(2, 1, 1, 9),
                           MakeShape(3, 2, 17, 1), MakeShape(4, 2, 64, 64)}) {
    for (int kind = 0; kind < 3; ++kind) {
      std::vector<uint8_t> m =
          kind == 0 ? MovingDiscs(s) : std::vector<uint8_t>(s.count(), kind == 2);
      if (kind == 2) {
        for (auto& v : m) v = rng() & 1;
      }
      const std::vector<uint8_t> coded = EncodeMasks(m.data(), s);
      std::vector<uint8_t> back(s.count(), 7);
      ASSERT_TRUE(DecodeMasks(coded.data(), coded.size(), s, back.data()).ok());
      EXPECT_EQ(back, m);
    }
  }
}

TEST(MaskCoder, TemporalContextPaysOff) {
  const Shape4D s = MakeShape(8, 1, 128, 128);
  const std::vector<uint8_t> m = MovingDiscs(s);
  const size_t all = EncodeMasks(m.data(), s).size();
  const Shape4D one = MakeShape(1, 1, 128, 128);
  const size_t first = EncodeMasks(m.data(), one).size();
  // Seven more frames of a slowly moving disc cost less than seven more intra frames.
  EXPECT_LT(all, first * 4) << all << " vs first frame " << first;
}

TEST(MaskCoder, TruncatedDataIsAnError) {
  const Shape4D s = MakeShape(4, 2, 40, 40);
  const std::vector<uint8_t> m = MovingDiscs(s);
  const std::vector<uint8_t> coded = EncodeMasks(m.data(), s);
  std::vector<uint8_t> back(s.count());
  for (size_t n = 0; n < coded.size(); ++n) {
    EXPECT_FALSE(DecodeMasks(coded.data(), n, s, back.data()).ok()) << n;
  }
  std::mt19937 rng(3);
  for (int i = 0; i < 200; ++i) {  // random bytes: decode or error, never a crash
    std::vector<uint8_t> junk(rng() % 64);
    for (auto& b : junk) b = rng();
    (void)DecodeMasks(junk.data(), junk.size(), s, back.data());
  }
}

}  // namespace
}  // namespace fvv
