// Bit-exact rotation arithmetic for the motion track (SPEC.md 6.4): angles as
// binary fractions of a turn, sines and cosines by CORDIC, unit quaternions in
// Q30 fixed point, slerp. Integer-only, so every decoder produces the same poses
// and conformance can hash them.
#ifndef FVV_CONTAINER_FIXED_ROTATION_H_
#define FVV_CONTAINER_FIXED_ROTATION_H_

#include <array>
#include <cstdint>

#include "container/body_model.h"

namespace fvv {

constexpr int64_t kQ30One = int64_t{1} << 30;

// w, x, y, z; a unit quaternion has w^2 + x^2 + y^2 + z^2 ~= 2^60.
struct QuatQ30 {
  std::array<int32_t, 4> c{static_cast<int32_t>(kQ30One), 0, 0, 0};
  bool operator==(const QuatQ30& o) const { return c == o.c; }
};

// sin and cos (Q30) of `angle` in units of 2^-32 turn.
void SinCosTurns(uint32_t angle, int32_t* sine, int32_t* cosine);
// atan2(y, x) for 0 <= x, y < 2^40, not both 0, in units of 2^-32 turn (0 .. 2^30).
int64_t Atan2Turns(int64_t y, int64_t x);
// floor(sqrt(v)).
uint64_t Isqrt(uint64_t v);

QuatQ30 QuatMultiply(const QuatQ30& a, const QuatQ30& b);
QuatQ30 QuatNormalize(const QuatQ30& q);
// Rotation by angle (2^-32 turns, any int64) about axis 0/1/2 (x/y/z).
QuatQ30 AxisRotation(int axis, int64_t angle);
// Euler angles (2^-32 turns, indexed by axis x y z) composed in `order`.
QuatQ30 EulerToQuat(RotationOrder order, const std::array<int64_t, 3>& angles);
// Spherical interpolation at fraction num/den (0 <= num <= den, den > 0), along
// the shorter arc.
QuatQ30 QuatSlerp(const QuatQ30& a, const QuatQ30& b, uint32_t num, uint32_t den);

}  // namespace fvv

#endif  // FVV_CONTAINER_FIXED_ROTATION_H_
