// Fixed-point rotation arithmetic: accuracy against double precision, and
// pinned outputs (the motion track's bit-exactness rests on these).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "container/fixed_rotation.h"

namespace fvv {
namespace {

constexpr double kTurn = 4294967296.0;

double ToDouble(int64_t q30) { return q30 / double(kQ30One); }

TEST(FixedRotation, SinCosMatchesLibmToQ30Precision) {
  std::mt19937 rng(1);
  double worst = 0;
  for (int i = 0; i < 20000; ++i) {
    const uint32_t a = i < 8 ? uint32_t(i) << 29 : rng();
    int32_t s, c;
    SinCosTurns(a, &s, &c);
    const double rad = a / kTurn * 2 * M_PI;
    worst = std::max(
        {worst, std::fabs(ToDouble(s) - std::sin(rad)), std::fabs(ToDouble(c) - std::cos(rad))});
  }
  EXPECT_LT(worst, 1.2e-8);  // ~13 Q30 units: 7e-7 degree, far below any quantisation step
}

TEST(FixedRotation, Atan2MatchesLibm) {
  std::mt19937 rng(2);
  for (int i = 0; i < 5000; ++i) {
    // Slerp calls it with unit-length (Q30) vectors.
    const double a = (rng() / 4294967296.0) * M_PI / 2;
    const int64_t x = std::llround(std::cos(a) * kQ30One), y = std::llround(std::sin(a) * kQ30One);
    const double expected = std::atan2(double(y), double(x)) / (2 * M_PI) * kTurn;
    EXPECT_NEAR(double(Atan2Turns(y, x)), expected, 16.0) << x << " " << y;
  }
}

TEST(FixedRotation, IsqrtIsExactFloor) {
  std::mt19937_64 rng(3);
  for (int i = 0; i < 10000; ++i) {
    const uint64_t v = rng() >> (rng() % 64);
    const uint64_t r = Isqrt(v);
    EXPECT_LE(r * r, v);
    EXPECT_GT((r + 1) * (r + 1), v);  // no overflow: r < 2^32
  }
  EXPECT_EQ(Isqrt(0), 0u);
  EXPECT_EQ(Isqrt(UINT64_MAX), 0xFFFFFFFFu);
}

// Reference in doubles: R = R_a0 * R_a1 * R_a2 as quaternions.
std::array<double, 4> EulerRef(RotationOrder order, const std::array<double, 3>& rad) {
  auto mul = [](const std::array<double, 4>& a, const std::array<double, 4>& b) {
    return std::array<double, 4>{a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
                                 a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
                                 a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
                                 a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]};
  };
  std::array<double, 4> q{1, 0, 0, 0};
  for (int axis : RotationOrderAxes(order)) {
    std::array<double, 4> r{std::cos(rad[axis] / 2), 0, 0, 0};
    r[1 + axis] = std::sin(rad[axis] / 2);
    q = mul(q, r);
  }
  return q;
}

TEST(FixedRotation, EulerToQuatMatchesDoubleReference) {
  std::mt19937 rng(4);
  std::uniform_int_distribution<int64_t> angle(-2000000000, 2000000000);
  for (int order = 0; order < kRotationOrderCount; ++order) {
    for (int i = 0; i < 300; ++i) {
      std::array<int64_t, 3> a{angle(rng), angle(rng), angle(rng)};
      std::array<double, 3> rad;
      for (int k = 0; k < 3; ++k) rad[k] = a[k] / kTurn * 2 * M_PI;
      const QuatQ30 q = EulerToQuat(static_cast<RotationOrder>(order), a);
      const auto ref = EulerRef(static_cast<RotationOrder>(order), rad);
      for (int k = 0; k < 4; ++k) EXPECT_NEAR(ToDouble(q.c[k]), ref[k], 2e-8);
    }
  }
}

std::array<double, 4> SlerpRef(std::array<double, 4> a, std::array<double, 4> b, double s) {
  double dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
  if (dot < 0) {
    for (double& v : b) v = -v;
    dot = -dot;
  }
  const double th = std::acos(std::min(1.0, dot));
  std::array<double, 4> r;
  for (int k = 0; k < 4; ++k) {
    r[k] =
        th < 1e-9 ? a[k] : (std::sin((1 - s) * th) * a[k] + std::sin(s * th) * b[k]) / std::sin(th);
  }
  return r;
}

TEST(FixedRotation, SlerpMatchesDoubleReferenceAndStaysUnit) {
  std::mt19937 rng(5);
  std::uniform_int_distribution<int64_t> angle(-1500000000, 1500000000);
  std::uniform_int_distribution<int64_t> small(-3000000, 3000000);  // near-identical rotations
  for (int i = 0; i < 2000; ++i) {
    const bool near = i % 4 == 0;
    std::array<int64_t, 3> a0{angle(rng), angle(rng), angle(rng)}, a1 = a0;
    for (auto& v : a1) v += near ? small(rng) : angle(rng);
    const QuatQ30 q0 = EulerToQuat(RotationOrder::kZYX, a0);
    const QuatQ30 q1 = EulerToQuat(RotationOrder::kZYX, a1);
    const uint32_t den = 1 + rng() % 16, num = rng() % (den + 1);
    const QuatQ30 q = QuatSlerp(q0, q1, num, den);
    std::array<double, 4> d0, d1;
    for (int k = 0; k < 4; ++k) {
      d0[k] = ToDouble(q0.c[k]);
      d1[k] = ToDouble(q1.c[k]);
    }
    auto ref = SlerpRef(d0, d1, double(num) / den);
    // q and -q are the same rotation (at num == den the key frame itself is returned).
    double sign = 0;
    for (int k = 0; k < 4; ++k) sign += ref[k] * q.c[k];
    if (sign < 0) {
      for (double& v : ref) v = -v;
    }
    double norm = 0;
    for (int k = 0; k < 4; ++k) {
      EXPECT_NEAR(ToDouble(q.c[k]), ref[k], 2e-7) << "num/den " << num << "/" << den;
      norm += ToDouble(q.c[k]) * ToDouble(q.c[k]);
    }
    EXPECT_NEAR(norm, 1.0, 1e-8);
  }
}

TEST(FixedRotation, OutputsArePinned) {
  // FNV-1a over a fixed sweep: any change to the integer arithmetic (and so to
  // decoded poses) shows here before it reaches the conformance hashes.
  uint64_t h = 0xcbf29ce484222325ull;
  auto mix = [&h](int64_t v) {
    for (int i = 0; i < 8; ++i) h = (h ^ ((uint64_t(v) >> (8 * i)) & 0xFF)) * 0x100000001b3ull;
  };
  for (int i = 0; i < 64; ++i) {
    const int64_t a = int64_t(i) * 67108859 - 2000000000;
    const QuatQ30 q0 = EulerToQuat(RotationOrder(i % 6), {a, a / 3, -a / 7});
    const QuatQ30 q1 = EulerToQuat(RotationOrder(i % 6), {a / 2 + 12345678, a / 5, a / 11});
    const QuatQ30 s = QuatSlerp(q0, q1, uint32_t(i % 7), 7);
    for (int32_t v : s.c) mix(v);
    int32_t sn, cs;
    SinCosTurns(uint32_t(a), &sn, &cs);
    mix(sn);
    mix(cs);
  }
  EXPECT_EQ(h, 0x80c6e72c9e464a46ull) << std::hex << "pinned value: 0x" << h;
}

}  // namespace
}  // namespace fvv
