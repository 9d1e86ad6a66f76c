// Bone transforms of a decoded frame (SPEC.md 6.1): the bit-exact BoneMotion
// of the motion track applied to the skeleton's rest pose, as float matrices a
// renderer uses directly.
#ifndef FVV_PLAYER_DECODER_POSE_H_
#define FVV_PLAYER_DECODER_POSE_H_

#include <glm/mat4x4.hpp>
#include <vector>

#include "container/body_model.h"
#include "container/motion_track.h"

namespace fvv {

// World transforms of the rest pose (no DOF motion).
std::vector<glm::mat4> RestWorldTransforms(const Skeleton& skeleton);
// World transforms of a pose; `motion` has one entry per bone.
std::vector<glm::mat4> WorldTransforms(const Skeleton& skeleton,
                                       const std::vector<BoneMotion>& motion);

}  // namespace fvv

#endif  // FVV_PLAYER_DECODER_POSE_H_
