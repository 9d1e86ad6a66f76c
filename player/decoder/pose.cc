#include "player/decoder/pose.h"

#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

namespace fvv {
namespace {

glm::mat4 Local(const Bone& bone, const BoneMotion* motion) {
  glm::vec3 t(bone.rest_translation[0], bone.rest_translation[1], bone.rest_translation[2]);
  glm::quat rest(bone.rest_rotation[0], bone.rest_rotation[1], bone.rest_rotation[2],
                 bone.rest_rotation[3]);
  glm::quat dof(1, 0, 0, 0);
  if (motion) {
    for (int a = 0; a < 3; ++a) t[a] += static_cast<float>(motion->translation_um[a] * 1e-6);
    const double s = 1.0 / static_cast<double>(kQ30One);
    dof = glm::quat(static_cast<float>(motion->rotation.c[0] * s),
                    static_cast<float>(motion->rotation.c[1] * s),
                    static_cast<float>(motion->rotation.c[2] * s),
                    static_cast<float>(motion->rotation.c[3] * s));
  }
  glm::mat4 m = glm::mat4_cast(glm::normalize(rest * dof));
  m[3] = glm::vec4(t, 1.0f);
  return m;
}

std::vector<glm::mat4> Chain(const Skeleton& skeleton, const std::vector<BoneMotion>* motion) {
  std::vector<glm::mat4> world(skeleton.bones.size());
  for (size_t b = 0; b < skeleton.bones.size(); ++b) {
    const Bone& bone = skeleton.bones[b];
    const glm::mat4 local = Local(bone, motion && b < motion->size() ? &(*motion)[b] : nullptr);
    world[b] = bone.parent >= 0 ? world[bone.parent] * local : local;  // parents come first
  }
  return world;
}

}  // namespace

std::vector<glm::mat4> RestWorldTransforms(const Skeleton& skeleton) {
  return Chain(skeleton, nullptr);
}

std::vector<glm::mat4> WorldTransforms(const Skeleton& skeleton,
                                       const std::vector<BoneMotion>& motion) {
  return Chain(skeleton, &motion);
}

}  // namespace fvv
