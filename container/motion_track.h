// The motion track, shaped like MPEG-4 AFX bone-based animation (SPEC.md 6):
// the skeleton is defined once in the body model; the 'mtrk' box declares the
// quantisation steps and coding mode; each fragment's 'motn' box codes the
// poses of its frames, starting with a key frame so the GOP decodes alone.
// Per coded frame: an animation mask (which bones, and which of their DOFs,
// change) and the changed values, predicted from earlier frames of the fragment
// and entropy coded. Optional key-frame interpolation (linear translation,
// slerp rotation) fills the frames between coded ones, bit-exactly.
#ifndef FVV_CONTAINER_MOTION_TRACK_H_
#define FVV_CONTAINER_MOTION_TRACK_H_

#include <array>
#include <cstdint>
#include <vector>

#include "codec/base/status.h"
#include "container/body_model.h"
#include "container/box.h"
#include "container/fixed_rotation.h"

namespace fvv {

enum class MotionCoder : uint8_t { kArith = 0, kZstd = 1 };

struct MotionParams {
  // Rotation step in 2^-32 turn: 596523 is 0.05 degree (error <= 0.025 degree).
  uint32_t rotation_step = 596523;
  uint32_t translation_step_um = 500;  // micrometres: 0.5 mm
  MotionCoder coder = MotionCoder::kArith;
  // 1: every frame is coded. N > 1: frames 0, N, 2N, ... and the last frame of
  // each fragment are coded; the frames between are interpolated.
  uint16_t key_interval = 1;

  // Stream statistics an offline encoder measures over the whole motion (empty
  // when it cannot, e.g. live): they let every fragment start where a long
  // stream would have adapted to, while each still decodes on its own.
  // Per DOF (skeleton order): the value key frames are coded against, and the
  // residual context class of a fragment's first predicted frame.
  std::vector<int32_t> key_reference;
  std::vector<uint8_t> first_class;
  // Initial probabilities of arithmetic-coder contexts: (context index, 15-bit
  // probability of 0 of the form p8 * 128 + 64, p8 in 1..254), increasing
  // indices; contexts not listed start at 16384.
  std::vector<std::pair<uint16_t, uint16_t>> context_init;

  double rotation_step_degrees() const { return rotation_step * (360.0 / 4294967296.0); }
};

std::vector<uint8_t> WriteMotionParamsBox(const MotionParams& p);
Status ReadMotionParams(const BoxHeader& box, const uint8_t* payload, MotionParams* p);
Status ValidateMotionParams(const MotionParams& p);

// A pose as the stream carries it: one integer per skeleton DOF (Skeleton::Dofs
// order), rotations in rotation steps, translations in translation steps.
using QuantisedPose = std::vector<int32_t>;

// Float pose (radians, metres per DOF) <-> quantised, rounding to nearest.
QuantisedPose QuantisePose(const std::vector<DofRef>& dofs, const MotionParams& p,
                           const std::vector<double>& values);
std::vector<double> DequantisePose(const std::vector<DofRef>& dofs, const MotionParams& p,
                                   const QuantisedPose& q);

// A decoded bone: the rotation and translation its DOFs contribute on top of the
// rest transform (bit-exact integers).
struct BoneMotion {
  QuatQ30 rotation;
  std::array<int64_t, 3> translation_um{};
};

struct DecodedFrame {
  bool coded = false;    // false: interpolated
  QuantisedPose values;  // the DOF values (coded frames; empty when interpolated)
  std::vector<BoneMotion> bones;
};

// Frames of a fragment that carry values: 0, N, 2N, ... and frame_count - 1.
std::vector<uint32_t> CodedFrameIndices(uint32_t frame_count, uint16_t key_interval);

// Encodes the poses of one fragment's frames (poses.size() frames; only the
// coded ones are used). Returns the 'motn' payload.
StatusOr<std::vector<uint8_t>> EncodeMotion(const Skeleton& skeleton, const MotionParams& p,
                                            const std::vector<QuantisedPose>& poses);
// Decodes a 'motn' payload into frame_count frames.
Status DecodeMotion(const BoxHeader& box, const uint8_t* payload, const Skeleton& skeleton,
                    const MotionParams& p, uint32_t frame_count, std::vector<DecodedFrame>* frames);

// Measures the stream statistics above from all poses of a stream (coded as
// fragments of gop_frames) and stores them in *p.
void TrainMotionParams(const Skeleton& skeleton, const std::vector<QuantisedPose>& poses,
                       uint32_t gop_frames, MotionParams* p);

// Bone motions of a coded pose (rotation from the bone's Euler DOFs in its
// rotation order, translation in micrometres).
std::vector<BoneMotion> BoneMotionsFromPose(const Skeleton& skeleton, const MotionParams& p,
                                            const QuantisedPose& pose);

}  // namespace fvv

#endif  // FVV_CONTAINER_MOTION_TRACK_H_
