// What the motion encoder and decoder share (SPEC.md 6.3): the context model of
// the arithmetic-coded residuals, the prediction rule, the mask structure.
#ifndef FVV_CONTAINER_MOTION_COMMON_H_
#define FVV_CONTAINER_MOTION_COMMON_H_

#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include "codec/range_coder.h"
#include "container/motion_track.h"

namespace fvv {
namespace motion {

// Motion streams are short (a few hundred decisions per fragment), so their
// probabilities adapt faster than SPIHT's.
constexpr int kAdaptShift = 4;
constexpr int kClasses = 12;  // residual magnitude classes of the previous frame; 11 = none
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

// All contexts, numbered in declaration order (SPEC.md 6.3) for the
// initialisation table of the 'mtrk' box.
struct Contexts {
  explicit Contexts(const std::vector<std::pair<uint16_t, uint16_t>>& init) {
    uint16_t* p = data();
    for (size_t i = 0; i < kCount; ++i) p[i] = kProbInit;
    for (const auto& ci : init) p[ci.first] = ci.second;
  }
  uint16_t* data() { return reinterpret_cast<uint16_t*>(this); }
  ResidualContexts residual[2][2];  // [translation][predicted]
  uint16_t bone_changed[2];         // by the bone's bit in the previous coded frame
  uint16_t dof_changed[2];          // by the DOF's bit in the previous coded frame
  static constexpr size_t kCount = (sizeof(ResidualContexts) * 4 + 8) / sizeof(uint16_t);
};
constexpr size_t kContextCount = Contexts::kCount;

inline int ResidualClass(bool has_previous, int64_t previous_residual) {
  if (!has_previous) return kClasses - 1;
  const int n = BitLength(
      static_cast<uint64_t>(previous_residual < 0 ? -previous_residual : previous_residual));
  return n < kClasses - 1 ? n : kClasses - 2;
}

// The binarisation of a residual (SPEC.md 6.3), for any `flag(bit, prob)` that
// codes one decision; lower mantissa bits use a fresh, unadapted probability.
// *too_long is set (and 0 returned) when a decoded length passes any valid one.
template <class Flag>
int64_t CodeResidualBins(Flag&& flag, int64_t r, ResidualContexts& c, int cls, bool* too_long) {
  if (!flag(r != 0, &c.zero[cls])) return 0;
  const bool negative = flag(r < 0, &c.sign) != 0;
  const uint64_t m_in = static_cast<uint64_t>(r < 0 ? -r : r);
  const int n_in = BitLength(m_in);
  int n = 1;
  while (flag(n < n_in, &c.length[cls][n - 1 < kMaxLengthBins ? n - 1 : kMaxLengthBins - 1])) {
    if (++n > 34) {
      *too_long = true;
      return 0;
    }
  }
  uint64_t m = 1;
  for (int i = n - 2; i >= 0; --i) {
    uint16_t even = kProbInit;
    m = (m << 1) | flag((m_in >> i) & 1, i == n - 2 ? &c.mantissa[n] : &even);
  }
  const int64_t v = static_cast<int64_t>(m);
  return negative ? -v : v;
}

// Bone index ranges into the DOF list: dofs of bone b are [first[b], first[b+1]).
std::vector<uint32_t> BoneDofStarts(const Skeleton& skeleton);

// Fills interpolated frames between coded ones (SPEC.md 6.4).
void Interpolate(const std::vector<uint32_t>& coded_indices, std::vector<DecodedFrame>* frames);

// The order in which a fragment's motion decisions are coded (SPEC.md 6.3),
// written once for encoder and decoder: `Side` either writes the decisions it is
// given or reads them and returns what it read, for either coder (arith: binary
// decisions with adaptive contexts; zstd: bytes, compressed as a whole).
// `coded`: K poses of D values. The encoder fills them before the call; the
// decoder sizes them and gets them filled. False when a decoded value leaves
// the int32 range (a corrupt stream).
template <class Side>
bool TraverseMotion(Side& side, const Skeleton& skeleton, const MotionParams& params,
                    Predictor predictor, std::vector<QuantisedPose>* coded) {
  const std::vector<uint32_t> starts = BoneDofStarts(skeleton);
  const size_t bone_count = skeleton.bones.size();
  const size_t dof_count = starts.back();
  const std::vector<DofRef> dofs = skeleton.Dofs();
  static_assert(sizeof(Contexts) == Contexts::kCount * sizeof(uint16_t), "packed contexts");
  Contexts ctx(params.context_init);
  side.Begin(ctx.data());
  const bool has_stats = params.key_reference.size() == dof_count;
  std::vector<uint8_t> prev_bone_changed(bone_count, 1), prev_dof_changed(dof_count, 1);
  std::vector<int64_t> prev_residual(dof_count, 0);
  auto& poses = *coded;
  auto store = [&](size_t j, size_t d, int64_t v) {
    if (v < std::numeric_limits<int32_t>::min() || v > std::numeric_limits<int32_t>::max()) {
      return false;
    }
    poses[j][d] = static_cast<int32_t>(v);
    return true;
  };
  for (size_t j = 0; j < poses.size(); ++j) {
    if (j == 0) {  // key frame: every DOF, predicted from the rest pose (0)
      for (size_t d = 0; d < dof_count; ++d) {
        const bool translation = !IsRotationDof(dofs[d].kind);
        const int64_t ref = has_stats ? params.key_reference[d] : 0;
        const int64_t r = side.Residual(poses[0][d] - ref, ctx.residual[translation][0], 0);
        if (!store(0, d, ref + r)) return false;
      }
      if (!side.ok()) return false;
      continue;
    }
    for (size_t b = 0; b < bone_count; ++b) {
      if (starts[b] == starts[b + 1]) continue;
      bool any = false;
      for (uint32_t d = starts[b]; d < starts[b + 1]; ++d) any |= poses[j][d] != poses[j - 1][d];
      const uint32_t bone_changed = side.Flag(any, &ctx.bone_changed[prev_bone_changed[b]]);
      prev_bone_changed[b] = static_cast<uint8_t>(bone_changed);
      for (uint32_t d = starts[b]; d < starts[b + 1]; ++d) {
        const bool translation = !IsRotationDof(dofs[d].kind);
        uint32_t changed = 0;
        if (bone_changed) {
          changed =
              side.Flag(poses[j][d] != poses[j - 1][d], &ctx.dof_changed[prev_dof_changed[d]]);
        }
        prev_dof_changed[d] = static_cast<uint8_t>(changed);
        int64_t r = 0, v = poses[j - 1][d];
        if (changed) {
          const int64_t pred = Predict(predictor, poses, j, d);
          const int cls = j >= 2      ? ResidualClass(true, prev_residual[d])
                          : has_stats ? params.first_class[d]
                                      : kClasses - 1;
          r = side.Residual(int64_t{poses[j][d]} - pred, ctx.residual[translation][1], cls);
          v = pred + r;
        }
        prev_residual[d] = r;
        if (!store(j, d, v)) return false;
      }
    }
    if (!side.ok()) return false;
  }
  return side.ok();
}

}  // namespace motion
}  // namespace fvv

#endif  // FVV_CONTAINER_MOTION_COMMON_H_
