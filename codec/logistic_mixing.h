// Integer logistic mixing for binary context models (SPEC.md 7.2): a
// probability moves to the logit ("stretch") domain, two models' logits are
// summed with a fixed weight, and the sum returns through the logistic
// ("squash") function. Everything is integer and table-driven so that encoder
// and decoder agree bit for bit on every platform.
//
// Also the count-adaptive probability both mask models use: a context that has
// seen few decisions adapts fast (1/2, 1/4, ...), one that has seen many adapts
// by 1/32, so the thousands of contexts of a fragment learn quickly.
#ifndef FVV_CODEC_LOGISTIC_MIXING_H_
#define FVV_CODEC_LOGISTIC_MIXING_H_

#include <array>
#include <cstdint>

#include "codec/range_coder.h"

namespace fvv {
namespace mixing {

// 15-bit probability of a 0 plus how many decisions (up to kMaxCount) it has seen.
struct CountedProb {
  uint16_t p0 = kProbInit;
  uint8_t count = 0;
};
constexpr uint8_t kMaxCount = 4;

inline void Update(uint32_t bit, CountedProb* m) {
  const int shift = m->count + 1;  // 1, 2, 3, 4, then 5 for good
  if (bit == 0) {
    m->p0 = static_cast<uint16_t>(m->p0 + (((1u << kProbBits) - m->p0) >> shift));
  } else {
    m->p0 = static_cast<uint16_t>(m->p0 - (m->p0 >> shift));
  }
  if (m->count < kMaxCount) ++m->count;
}

// 12-bit probability of a 1 (0..4095) from a model's 15-bit probability of a 0.
inline int ProbOne12(const CountedProb& m) { return static_cast<int>((32768u - m.p0) >> 3); }

// squash(d) = 4096 / (1 + e^(-d/256)) for d in [-2047, 2047] by linear
// interpolation between the logistic at every half unit (SPEC.md table 7.2).
inline int Squash(int d) {
  static constexpr int16_t kKnots[33] = {1,    2,    4,    6,    10,   17,   27,   45,   74,
                                         120,  194,  311,  488,  747,  1102, 1546, 2048, 2550,
                                         2994, 3349, 3608, 3785, 3902, 3976, 4022, 4051, 4069,
                                         4079, 4086, 4090, 4092, 4094, 4095};
  if (d > 2047) d = 2047;
  if (d < -2047) d = -2047;
  const int w = d & 127;          // d mod 128, in [0, 127] (two's complement)
  const int i = (d + 2048) >> 7;  // floor(d / 128) + 16, in [0, 31]
  return (kKnots[i] * (128 - w) + kKnots[i + 1] * w + 64) >> 7;
}

// floor(a * b / 256) for a possibly negative a, without relying on how >> treats
// negative numbers.
inline int FloorMulShift8(int a, int b) {
  const int prod = a * b;
  return prod >= 0 ? prod >> 8 : -((-prod + 255) >> 8);
}

// The mix of two models as the spec defines it (SPEC.md 7.2): the 15-bit
// probability of a 0 for the sum `stretch_sum` = stretch(qa) + stretch(qb),
// squash(floor(154 * stretch_sum / 256)) kept in [1, 4095].
constexpr int kMixWeight = 154;  // about 0.6 per model, in 1/256
inline uint32_t MixOfStretchSum(int stretch_sum) {
  int q = Squash(FloorMulShift8(stretch_sum, kMixWeight));
  if (q < 1) q = 1;
  if (q > 4095) q = 4095;
  return static_cast<uint32_t>(4096 - q) << 3;
}

// The per-texel work as two table lookups: stretch(q) for q in [0, 4095], the
// least d in [-2047, 2047] with squash(d) >= q, else 2047; and the mix of every
// possible stretch sum.
class MixTables {
 public:
  static constexpr int kMaxStretch = 2047;
  MixTables() {
    int q = 0;
    for (int d = -kMaxStretch; d <= kMaxStretch; ++d) {
      const int s = Squash(d);
      while (q <= s && q < 4096) stretch_[q++] = static_cast<int16_t>(d);
    }
    while (q < 4096) stretch_[q++] = kMaxStretch;
    for (int sum = -2 * kMaxStretch; sum <= 2 * kMaxStretch; ++sum)
      mix_[sum + 2 * kMaxStretch] = static_cast<uint16_t>(MixOfStretchSum(sum));
  }
  int Stretch(int q) const { return stretch_[q]; }
  // The range coder's 15-bit probability of a 0 for models a and b.
  uint32_t MixedProbZero(const CountedProb& a, const CountedProb& b) const {
    return mix_[Stretch(ProbOne12(a)) + Stretch(ProbOne12(b)) + 2 * kMaxStretch];
  }

 private:
  std::array<int16_t, 4096> stretch_{};
  std::array<uint16_t, 4 * kMaxStretch + 1> mix_{};
};

inline const MixTables& Tables() {
  static const MixTables tables;
  return tables;
}

}  // namespace mixing
}  // namespace fvv

#endif  // FVV_CODEC_LOGISTIC_MIXING_H_
