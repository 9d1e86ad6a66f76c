#include "container/motion_common.h"

#include <cmath>
#include <string>

namespace fvv {

std::vector<uint8_t> WriteMotionParamsBox(const MotionParams& p) {
  ByteWriter w;
  w.U32(p.rotation_step);
  w.U32(p.translation_step_um);
  w.U8(static_cast<uint8_t>(p.coder));
  w.U16(p.key_interval);
  w.U16(static_cast<uint32_t>(p.key_reference.size()));
  for (int32_t v : p.key_reference) w.I32(v);
  for (uint8_t c : p.first_class) w.U8(c);
  w.U16(static_cast<uint32_t>(p.context_init.size()));
  for (const auto& ci : p.context_init) {
    w.U16(ci.first);
    w.U8(ci.second >> 7);
  }
  return MakeBox(box::kMotionParams, 0, kBoxFlagEssential, w.bytes());
}

Status ValidateMotionParams(const MotionParams& p) {
  if (p.rotation_step == 0 || p.rotation_step > (1u << 26)) {
    return Corrupt("motion params: rotation step " + std::to_string(p.rotation_step) +
                   " outside 1..2^26 (2^-32 turn units)");
  }
  if (p.translation_step_um == 0 || p.translation_step_um > 1000000) {
    return Corrupt("motion params: translation step " + std::to_string(p.translation_step_um) +
                   " um outside 1..1000000");
  }
  if (p.coder != MotionCoder::kArith && p.coder != MotionCoder::kZstd) {
    return Unsupported("motion params: coder " + std::to_string(int(p.coder)));
  }
  if (p.key_interval == 0 || p.key_interval > 256) {
    return Corrupt("motion params: key interval " + std::to_string(p.key_interval) +
                   " outside 1..256");
  }
  if (p.first_class.size() != p.key_reference.size()) {
    return Corrupt("motion params: per-DOF statistics of different lengths");
  }
  for (uint8_t c : p.first_class) {
    if (c >= motion::kClasses) return Corrupt("motion params: first class " + std::to_string(c));
  }
  for (size_t i = 0; i < p.context_init.size(); ++i) {
    const auto& ci = p.context_init[i];
    if (ci.first >= motion::kContextCount || ci.second < 128 || ci.second >= (255u << 7) ||
        (ci.second & 127) != 64 || (i > 0 && ci.first <= p.context_init[i - 1].first)) {
      return Corrupt("motion params: context initialisation entry " + std::to_string(i) +
                     " is invalid");
    }
  }
  return Status::Ok();
}

Status ReadMotionParams(const BoxHeader& box, const uint8_t* payload, MotionParams* p) {
  if (box.version != 0)
    return Unsupported(BoxContext(box) + "version " + std::to_string(box.version));
  ByteReader r(payload, box.payload_bytes());
  p->rotation_step = r.U32();
  p->translation_step_um = r.U32();
  p->coder = static_cast<MotionCoder>(r.U8());
  p->key_interval = r.U16();
  const uint32_t dofs = r.U16();
  if (uint64_t{dofs} * 5 > r.remaining())
    return Corrupt(BoxContext(box) + "too short for its DOF statistics");
  p->key_reference.resize(dofs);
  for (int32_t& v : p->key_reference) v = r.I32();
  p->first_class.resize(dofs);
  for (uint8_t& c : p->first_class) c = r.U8();
  const uint32_t inits = r.U16();
  if (uint64_t{inits} * 3 != r.remaining()) return Corrupt(BoxContext(box) + "context table size");
  p->context_init.resize(inits);
  for (auto& ci : p->context_init) {
    ci.first = r.U16();
    const uint32_t p8 = r.U8();
    ci.second = static_cast<uint16_t>(p8 * 128 + 64);
    if (p8 == 0 || p8 == 255) return Corrupt(BoxContext(box) + "context probability 0 or 255");
  }
  FVV_RETURN_IF_ERROR(CheckFullyRead(r, box));
  return ValidateMotionParams(*p);
}

namespace {

int32_t ClampToInt32(double v) {
  if (!(v > -2147483647.0)) return -2147483647;  // also catches NaN
  if (v > 2147483647.0) return 2147483647;
  return static_cast<int32_t>(std::lround(v));
}

double RotationStepRadians(const MotionParams& p) {
  return p.rotation_step * (2.0 * M_PI / 4294967296.0);
}

}  // namespace

QuantisedPose QuantisePose(const std::vector<DofRef>& dofs, const MotionParams& p,
                           const std::vector<double>& values) {
  QuantisedPose q(dofs.size());
  const double rot = RotationStepRadians(p), trans = p.translation_step_um * 1e-6;
  for (size_t d = 0; d < dofs.size() && d < values.size(); ++d) {
    q[d] = ClampToInt32(values[d] / (IsRotationDof(dofs[d].kind) ? rot : trans));
  }
  return q;
}

std::vector<double> DequantisePose(const std::vector<DofRef>& dofs, const MotionParams& p,
                                   const QuantisedPose& q) {
  std::vector<double> v(dofs.size());
  const double rot = RotationStepRadians(p), trans = p.translation_step_um * 1e-6;
  for (size_t d = 0; d < dofs.size() && d < q.size(); ++d) {
    v[d] = q[d] * (IsRotationDof(dofs[d].kind) ? rot : trans);
  }
  return v;
}

std::vector<uint32_t> CodedFrameIndices(uint32_t frame_count, uint16_t key_interval) {
  std::vector<uint32_t> idx;
  if (frame_count == 0) return idx;
  for (uint32_t f = 0; f < frame_count; f += key_interval) idx.push_back(f);
  if (idx.back() != frame_count - 1) idx.push_back(frame_count - 1);
  return idx;
}

std::vector<BoneMotion> BoneMotionsFromPose(const Skeleton& skeleton, const MotionParams& p,
                                            const QuantisedPose& pose) {
  std::vector<BoneMotion> bones(skeleton.bones.size());
  size_t d = 0;
  for (size_t b = 0; b < skeleton.bones.size(); ++b) {
    const Bone& bone = skeleton.bones[b];
    std::array<int64_t, 3> angles{};
    for (int k = 0; k < kDofKinds; ++k) {
      if (!(bone.dof_mask & (1u << k))) continue;
      const int64_t v = d < pose.size() ? pose[d] : 0;
      ++d;
      if (IsRotationDof(k)) {
        angles[k] = v * p.rotation_step;
      } else {
        bones[b].translation_um[k - 3] = v * p.translation_step_um;
      }
    }
    if (bone.dof_mask & (kDofRotX | kDofRotY | kDofRotZ)) {
      bones[b].rotation = EulerToQuat(bone.order, angles);
    }
  }
  return bones;
}

namespace motion {

std::vector<uint32_t> BoneDofStarts(const Skeleton& skeleton) {
  std::vector<uint32_t> starts(skeleton.bones.size() + 1, 0);
  for (size_t b = 0; b < skeleton.bones.size(); ++b) {
    int n = 0;
    for (int k = 0; k < kDofKinds; ++k) n += (skeleton.bones[b].dof_mask >> k) & 1;
    starts[b + 1] = starts[b] + n;
  }
  return starts;
}

void Interpolate(const std::vector<uint32_t>& coded, std::vector<DecodedFrame>* frames) {
  for (size_t j = 0; j + 1 < coded.size(); ++j) {
    const uint32_t i0 = coded[j], i1 = coded[j + 1];
    const DecodedFrame& f0 = (*frames)[i0];
    const DecodedFrame& f1 = (*frames)[i1];
    for (uint32_t k = i0 + 1; k < i1; ++k) {
      DecodedFrame& f = (*frames)[k];
      f.coded = false;
      f.values.clear();
      f.bones.resize(f0.bones.size());
      const uint32_t num = k - i0, den = i1 - i0;
      for (size_t b = 0; b < f.bones.size(); ++b) {
        f.bones[b].rotation = QuatSlerp(f0.bones[b].rotation, f1.bones[b].rotation, num, den);
        for (int a = 0; a < 3; ++a) {
          const int64_t t0 = f0.bones[b].translation_um[a], t1 = f1.bones[b].translation_um[a];
          f.bones[b].translation_um[a] = t0 + (t1 - t0) * num / den;
        }
      }
    }
  }
}

}  // namespace motion
}  // namespace fvv
