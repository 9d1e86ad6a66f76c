// The order in which a fragment's motion decisions are coded (SPEC.md 6.3),
// written once for encoder and decoder: `Side` either writes the decisions it is
// given or reads them and returns what it read, for either coder (arith: binary
// decisions with adaptive contexts; zstd: bytes, compressed as a whole).
#ifndef FVV_CONTAINER_MOTION_TRAVERSAL_H_
#define FVV_CONTAINER_MOTION_TRAVERSAL_H_

#include <limits>

#include "container/motion_common.h"

namespace fvv {
namespace motion {

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

#endif  // FVV_CONTAINER_MOTION_TRAVERSAL_H_
