// An exported actor's motion as BVH (Biovision hierarchy) on the model's
// skeleton: each joint's offset from its parent in centimetres, the roots'
// position channels, and each joint's rotation as Euler angles in degrees in
// the joint's own rotation order (its rest rotation and its motion together,
// as BVH has no rest rotation). Leaf joints end in an End Site half their own
// offset further on, for tools that draw bones to it.
#ifndef FVV_PLAYER_EXPORT_BVH_WRITER_H_
#define FVV_PLAYER_EXPORT_BVH_WRITER_H_

#include <string>

#include "codec/base/status.h"
#include "player/export/exported_actor.h"

namespace fvv {

std::string BvhText(const ExportedActor& actor);
Status WriteBvh(const ExportedActor& actor, const std::string& path);

// Euler angles (radians) of a rotation in `order`: R = R_a0(e0) R_a1(e1)
// R_a2(e2), the axes of RotationOrderAxes; of the two solutions, the one
// nearer `previous` (each angle unwrapped to within pi of it).
glm::vec3 EulerAngles(const glm::quat& rotation, RotationOrder order, const glm::vec3& previous);

}  // namespace fvv

#endif  // FVV_PLAYER_EXPORT_BVH_WRITER_H_
