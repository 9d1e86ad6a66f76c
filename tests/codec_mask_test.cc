// Mask coder: lossless on structured and random masks in both modes, mode 2
// smaller than mode 1, safe on bad input; the mixing primitives' invariants.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "codec/logistic_mixing.h"
#include "codec/mask.h"

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

// Atlas-like masks: rectangles ("charts") whose visible part is cut by a wavy
// boundary that moves with time and differs per camera.
std::vector<uint8_t> MovingCharts(const Shape4D& s, uint32_t seed) {
  std::mt19937 rng(seed);
  struct Chart {
    int x0, y0, x1, y1;
    double phase;
  };
  std::vector<Chart> charts(24);
  for (Chart& ch : charts) {
    ch.x0 = int(rng() % s.width());
    ch.y0 = int(rng() % s.height());
    ch.x1 = ch.x0 + 4 + int(rng() % (s.width() / 4 + 1));
    ch.y1 = ch.y0 + 3 + int(rng() % (s.height() / 8 + 1));
    ch.phase = (rng() % 1000) * 0.00628;
  }
  std::vector<uint8_t> m(s.count(), 0);
  for (uint32_t t = 0; t < s.frames(); ++t)
    for (uint32_t c = 0; c < s.cameras(); ++c)
      for (const Chart& ch : charts)
        for (int y = ch.y0; y < std::min<int>(ch.y1, s.height()); ++y) {
          const double cut =
              ch.x0 +
              (ch.x1 - ch.x0) * (0.5 + 0.35 * std::sin(ch.phase + 0.3 * t + 0.9 * c + 0.2 * y));
          for (int x = ch.x0; x < std::min<int>(int(cut), s.width()); ++x) {
            m[s.Index(t, c, y, x)] = 1;
          }
        }
  return m;
}

class MaskModes : public ::testing::TestWithParam<MaskCoding> {};
INSTANTIATE_TEST_SUITE_P(Both, MaskModes,
                         ::testing::Values(MaskCoding::kContext, MaskCoding::kMixing));

TEST_P(MaskModes, RoundTripsExactly) {
  const MaskCoding mode = GetParam();
  std::mt19937 rng(11);
  for (const Shape4D& s : {MakeShape(8, 3, 33, 47), MakeShape(1, 1, 1, 1), MakeShape(2, 1, 1, 9),
                           MakeShape(3, 2, 17, 1), MakeShape(4, 2, 64, 64), MakeShape(5, 3, 40, 3),
                           MakeShape(6, 2, 48, 96)}) {
    for (int kind = 0; kind < 5; ++kind) {
      std::vector<uint8_t> m = kind == 0   ? MovingDiscs(s)
                               : kind == 3 ? MovingCharts(s, 5)
                                           : std::vector<uint8_t>(s.count(), kind != 1);
      if (kind == 2) {
        for (auto& v : m) v = rng() & 1;
      }
      const std::vector<uint8_t> coded = EncodeMasks(m.data(), s, mode);
      std::vector<uint8_t> back(s.count(), 7);
      ASSERT_TRUE(DecodeMasks(coded.data(), coded.size(), s, mode, back.data()).ok());
      EXPECT_EQ(back, m) << "kind " << kind;
    }
  }
}

TEST_P(MaskModes, TemporalContextPaysOff) {
  const Shape4D s = MakeShape(8, 1, 128, 128);
  const std::vector<uint8_t> m = MovingDiscs(s);
  const size_t all = EncodeMasks(m.data(), s, GetParam()).size();
  const Shape4D one = MakeShape(1, 1, 128, 128);
  const size_t first = EncodeMasks(m.data(), one, GetParam()).size();
  // Seven more frames of a slowly moving disc cost less than seven more intra frames.
  EXPECT_LT(all, first * 4) << all << " vs first frame " << first;
}

// Short data inside a whole box is Corrupt (SPEC.md 9.4: one rule with motion).
TEST_P(MaskModes, ShortDataIsCorrupt) {
  const MaskCoding mode = GetParam();
  const Shape4D s = MakeShape(4, 2, 40, 40);
  const std::vector<uint8_t> m = MovingDiscs(s);
  const std::vector<uint8_t> coded = EncodeMasks(m.data(), s, mode);
  std::vector<uint8_t> back(s.count());
  for (size_t n = 0; n < coded.size(); ++n) {
    const Status st = DecodeMasks(coded.data(), n, s, mode, back.data());
    EXPECT_EQ(st.code(), StatusCode::kCorrupt) << n;
  }
  std::mt19937 rng(3);
  for (int i = 0; i < 200; ++i) {  // random bytes: decode or error, never a crash
    std::vector<uint8_t> junk(rng() % 64);
    for (auto& b : junk) b = rng();
    (void)DecodeMasks(junk.data(), junk.size(), s, mode, back.data());
  }
}

TEST(MaskCoder, UnknownModeIsUnsupported) {
  const Shape4D s = MakeShape(1, 1, 8, 8);
  const std::vector<uint8_t> data(16, 0);
  std::vector<uint8_t> back(s.count());
  for (int mode : {0, 3, 255}) {
    const Status st =
        DecodeMasks(data.data(), data.size(), s, static_cast<MaskCoding>(mode), back.data());
    EXPECT_EQ(st.code(), StatusCode::kUnsupported) << mode;
  }
}

// Mode 2 exists to be smaller: on chart-like masks, on moving discs, and on a
// GOP of several cameras.
TEST(MaskCoder, MixingIsSmallerThanContextCoding) {
  for (const Shape4D& s : {MakeShape(8, 1, 256, 256), MakeShape(4, 4, 128, 192)}) {
    for (int kind = 0; kind < 2; ++kind) {
      const std::vector<uint8_t> m = kind == 0 ? MovingCharts(s, 9) : MovingDiscs(s);
      const size_t one = EncodeMasks(m.data(), s, MaskCoding::kContext).size();
      const size_t two = EncodeMasks(m.data(), s, MaskCoding::kMixing).size();
      EXPECT_LT(double(two), 0.95 * double(one)) << "kind " << kind << ": " << two << " vs " << one;
    }
  }
}

// squash is the logistic 4096 / (1 + e^(-d/256)) to within interpolation
// error, monotone; stretch is its least inverse.
TEST(LogisticMixing, SquashAndStretchAreInverse) {
  int last = 0;
  for (int d = -2047; d <= 2047; ++d) {
    const int q = mixing::Squash(d);
    EXPECT_GE(q, last);
    last = q;
    EXPECT_NEAR(q, 4096.0 / (1.0 + std::exp(-d / 256.0)), 16.0) << d;
  }
  EXPECT_EQ(mixing::Squash(0), 2048);
  EXPECT_EQ(mixing::Squash(5000), mixing::Squash(2047));
  const auto& tables = mixing::Tables();
  for (int q = 0; q < 4096; ++q) {
    const int d = tables.Stretch(q);
    if (d < 2047) {
      EXPECT_GE(mixing::Squash(d), q) << q;
    }
    if (d > -2047) {
      EXPECT_LT(mixing::Squash(d - 1), q) << q;
    }
  }
}

// Two confident models that agree give a more confident mix; a count-adaptive
// model moves by 1/2 on its first decision.
TEST(LogisticMixing, MixAndCountedAdaptation) {
  mixing::CountedProb m;
  mixing::Update(0, &m);
  EXPECT_EQ(m.p0, kProbInit + (kProbInit >> 1));
  for (int i = 0; i < 50; ++i) mixing::Update(0, &m);
  EXPECT_EQ(m.count, mixing::kMaxCount);
  const mixing::MixTables& tables = mixing::Tables();
  const uint32_t mixed = tables.MixedProbZero(m, m);
  EXPECT_GT(mixed, m.p0);
  EXPECT_LT(mixed, 32768u);
  mixing::CountedProb fresh;
  EXPECT_EQ(tables.MixedProbZero(fresh, fresh), 16384u);
}

// The mix table is the spec's formula for every pair of 15-bit model
// probabilities (stepped) and every stretch sum.
TEST(LogisticMixing, MixTableIsTheFormula) {
  const mixing::MixTables& tables = mixing::Tables();
  for (int sum = -4094; sum <= 4094; ++sum) {
    const int q = mixing::Squash(mixing::FloorMulShift8(sum, mixing::kMixWeight));
    ASSERT_EQ(mixing::MixOfStretchSum(sum), static_cast<uint32_t>(4096 - std::clamp(q, 1, 4095))
                                                << 3)
        << sum;
  }
  for (uint32_t pa = 1; pa < 32768; pa += 37) {
    for (uint32_t pb = 1; pb < 32768; pb += 53) {
      mixing::CountedProb a, b;
      a.p0 = static_cast<uint16_t>(pa);
      b.p0 = static_cast<uint16_t>(pb);
      const int sum = tables.Stretch(mixing::ProbOne12(a)) + tables.Stretch(mixing::ProbOne12(b));
      ASSERT_EQ(tables.MixedProbZero(a, b), mixing::MixOfStretchSum(sum)) << pa << " " << pb;
    }
  }
}

}  // namespace
}  // namespace fvv
