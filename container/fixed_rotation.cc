#include "container/fixed_rotation.h"

namespace fvv {
namespace {

constexpr int kCordicSteps = 30;
// round(atan(2^-i) / (2 pi) * 2^32): SPEC.md 6.4, table 6.
constexpr int64_t kAtanTurns[kCordicSteps] = {
    536870912, 316933406, 167458907, 85004756, 42667331, 21354465, 10679838, 5340245,
    2670163,   1335087,   667544,    333772,   166886,   83443,    41722,    20861,
    10430,     5215,      2608,      1304,     652,      326,      163,      81,
    41,        20,        10,        5,        3,        1};
// The CORDIC iterations run with 8 guard bits (Q38), so that the rounding of 30
// steps stays below one unit of the Q30 result.
constexpr int kGuardBits = 8;
// round(2^38 * prod_i 1 / sqrt(1 + 2^-2i)), i = 0..29: the CORDIC gain compensation.
constexpr int64_t kCordicGainQ38 = 166920415761;

// Arithmetic right shift, which SPEC.md defines as floor division by 2^n.
// (C++17 leaves >> of negative values implementation-defined.)
inline int64_t Asr(int64_t v, int n) { return v >= 0 ? v >> n : ~((~v) >> n); }

// Rounded Q60 -> Q30.
inline int64_t RoundQ30(int64_t v) { return Asr(v + (int64_t{1} << 29), 30); }

}  // namespace

void SinCosTurns(uint32_t angle, int32_t* sine, int32_t* cosine) {
  const uint32_t quadrant = angle >> 30;
  int64_t z = angle & 0x3FFFFFFFu;  // [0, a quarter turn)
  int64_t x = kCordicGainQ38, y = 0;
  for (int i = 0; i < kCordicSteps; ++i) {
    const int64_t dx = Asr(y, i), dy = Asr(x, i);
    if (z >= 0) {
      x -= dx;
      y += dy;
      z -= kAtanTurns[i];
    } else {
      x += dx;
      y -= dy;
      z += kAtanTurns[i];
    }
  }
  x = Asr(x + (int64_t{1} << (kGuardBits - 1)), kGuardBits);  // rounded Q38 -> Q30
  y = Asr(y + (int64_t{1} << (kGuardBits - 1)), kGuardBits);
  int64_t s, c;
  switch (quadrant) {
    case 0:
      s = y;
      c = x;
      break;
    case 1:
      s = x;
      c = -y;
      break;
    case 2:
      s = -y;
      c = -x;
      break;
    default:
      s = -x;
      c = y;
      break;
  }
  *sine = static_cast<int32_t>(s);
  *cosine = static_cast<int32_t>(c);
}

int64_t Atan2Turns(int64_t y, int64_t x) {
  x *= int64_t{1} << kGuardBits;
  y *= int64_t{1} << kGuardBits;
  int64_t z = 0;
  for (int i = 0; i < kCordicSteps; ++i) {
    const int64_t dx = Asr(y, i), dy = Asr(x, i);
    if (y > 0) {
      x += dx;
      y -= dy;
      z += kAtanTurns[i];
    } else {
      x -= dx;
      y += dy;
      z -= kAtanTurns[i];
    }
  }
  return z;
}

uint64_t Isqrt(uint64_t v) {
  uint64_t result = 0;
  uint64_t bit = uint64_t{1} << 62;
  while (bit > v) bit >>= 2;
  while (bit != 0) {
    if (v >= result + bit) {
      v -= result + bit;
      result = (result >> 1) + bit;
    } else {
      result >>= 1;
    }
    bit >>= 2;
  }
  return result;
}

QuatQ30 QuatMultiply(const QuatQ30& a, const QuatQ30& b) {
  const int64_t aw = a.c[0], ax = a.c[1], ay = a.c[2], az = a.c[3];
  const int64_t bw = b.c[0], bx = b.c[1], by = b.c[2], bz = b.c[3];
  QuatQ30 r;
  r.c[0] = static_cast<int32_t>(RoundQ30(aw * bw - ax * bx - ay * by - az * bz));
  r.c[1] = static_cast<int32_t>(RoundQ30(aw * bx + ax * bw + ay * bz - az * by));
  r.c[2] = static_cast<int32_t>(RoundQ30(aw * by - ax * bz + ay * bw + az * bx));
  r.c[3] = static_cast<int32_t>(RoundQ30(aw * bz + ax * by - ay * bx + az * bw));
  return r;
}

QuatQ30 QuatNormalize(const QuatQ30& q) {
  uint64_t n2 = 0;
  for (int32_t v : q.c) n2 += static_cast<uint64_t>(int64_t{v} * v);
  const int64_t norm = static_cast<int64_t>(Isqrt(n2));
  if (norm == 0) return QuatQ30();
  QuatQ30 r;
  for (int i = 0; i < 4; ++i) r.c[i] = static_cast<int32_t>(int64_t{q.c[i]} * kQ30One / norm);
  return r;
}

QuatQ30 AxisRotation(int axis, int64_t angle) {
  // Half angle by floor division; the wrap to 32 bits keeps the same sine and
  // cosine up to a common sign, i.e. the same rotation.
  const uint32_t half = static_cast<uint32_t>(static_cast<uint64_t>(Asr(angle, 1)));
  int32_t s, c;
  SinCosTurns(half, &s, &c);
  QuatQ30 q;
  q.c = {c, 0, 0, 0};
  q.c[1 + axis] = s;
  return q;
}

QuatQ30 EulerToQuat(RotationOrder order, const std::array<int64_t, 3>& angles) {
  const std::array<int, 3> axes = RotationOrderAxes(order);
  QuatQ30 q = AxisRotation(axes[0], angles[axes[0]]);
  q = QuatMultiply(q, AxisRotation(axes[1], angles[axes[1]]));
  return QuatMultiply(q, AxisRotation(axes[2], angles[axes[2]]));
}

QuatQ30 QuatSlerp(const QuatQ30& a, const QuatQ30& b_in, uint32_t num, uint32_t den) {
  if (num == 0) return a;
  if (num >= den) return b_in;
  QuatQ30 b = b_in;
  int64_t dot = 0;
  for (int i = 0; i < 4; ++i) dot += int64_t{a.c[i]} * b.c[i];
  dot = RoundQ30(dot);
  if (dot < 0) {
    for (int32_t& v : b.c) v = -v;
    dot = -dot;
  }
  if (dot > kQ30One) dot = kQ30One;
  QuatQ30 r;
  // Below ~0.3 degrees apart, slerp and linear interpolation agree to far below
  // Q30 precision, and sin(theta) would be too small to divide by.
  constexpr int64_t kLinearAbove = kQ30One - (int64_t{1} << 14);
  if (dot > kLinearAbove) {
    for (int i = 0; i < 4; ++i) {
      r.c[i] = static_cast<int32_t>(a.c[i] + (int64_t{b.c[i]} - a.c[i]) * num / den);
    }
    return QuatNormalize(r);
  }
  const int64_t sin_theta =
      static_cast<int64_t>(Isqrt(static_cast<uint64_t>(kQ30One * kQ30One - dot * dot)));
  const int64_t theta = Atan2Turns(sin_theta, dot);
  int32_t w0, w1, unused;
  SinCosTurns(static_cast<uint32_t>(theta * (den - num) / den), &w0, &unused);
  SinCosTurns(static_cast<uint32_t>(theta * num / den), &w1, &unused);
  for (int i = 0; i < 4; ++i) {
    r.c[i] = static_cast<int32_t>((int64_t{a.c[i]} * w0 + int64_t{b.c[i]} * w1) / sin_theta);
  }
  return QuatNormalize(r);
}

}  // namespace fvv
