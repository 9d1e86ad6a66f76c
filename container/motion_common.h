// What the motion encoder and decoder share (SPEC.md 6.3): the context model of
// the arithmetic-coded residuals, the prediction rule, the mask structure.
#ifndef FVV_CONTAINER_MOTION_COMMON_H_
#define FVV_CONTAINER_MOTION_COMMON_H_

#include <array>
#include <cstdint>
#include <vector>

#include "codec/range_coder.h"
#include "container/motion_track.h"

namespace fvv {
namespace motion {

// Motion streams are short (a few hundred decisions per fragment), so their
// probabilities adapt faster than SPIHT's.
constexpr int kAdaptShift = 4;
constexpr int kClasses = 12;      // residual magnitude classes of the previous frame; 11 = none
constexpr int kMaxLengthBins = 32;

enum Predictor : uint8_t { kPreviousValue = 0, kLinearExtrapolation = 1 };

inline int BitLength(uint64_t v) {
  int n = 0;
  while (v != 0) {
    ++n;
    v >>= 1;
  }
  return n;
}

inline int64_t Predict(Predictor predictor, const std::vector<QuantisedPose>& coded, size_t j,
                       size_t d) {
  if (j == 0) return 0;
  const int64_t p1 = coded[j - 1][d];
  if (predictor == kLinearExtrapolation && j >= 2) return 2 * p1 - coded[j - 2][d];
  return p1;
}

// One context set per (DOF kind: rotation/translation) x (key / predicted frame).
struct ResidualContexts {
  uint16_t zero[kClasses];
  uint16_t sign;
  uint16_t length[kClasses][kMaxLengthBins];
  uint16_t mantissa[35];  // by bit length: residuals reach 2^33 (second-order prediction of int32)
};

struct Contexts {
  Contexts() {
    uint16_t* p = reinterpret_cast<uint16_t*>(this);
    for (size_t i = 0; i < sizeof(Contexts) / sizeof(uint16_t); ++i) p[i] = kProbInit;
  }
  ResidualContexts residual[2][2];  // [translation][predicted]
  uint16_t bone_changed[2];         // by the bone's bit in the previous coded frame
  uint16_t dof_changed[2];          // by the DOF's bit in the previous coded frame
};

inline int ResidualClass(bool has_previous, int64_t previous_residual) {
  if (!has_previous) return kClasses - 1;
  const int n = BitLength(static_cast<uint64_t>(previous_residual < 0 ? -previous_residual
                                                                       : previous_residual));
  return n < kClasses - 1 ? n : kClasses - 2;
}

// Bone index ranges into the DOF list: dofs of bone b are [first[b], first[b+1]).
std::vector<uint32_t> BoneDofStarts(const Skeleton& skeleton);

// Fills interpolated frames between coded ones (SPEC.md 6.4).
void Interpolate(const std::vector<uint32_t>& coded_indices, std::vector<DecodedFrame>* frames);

}  // namespace motion
}  // namespace fvv

#endif  // FVV_CONTAINER_MOTION_COMMON_H_
