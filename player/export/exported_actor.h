// What the exporters write, gathered from an open decoder: the joint
// hierarchy with its rest pose, each exported frame's joint transforms (local,
// as glTF and BVH key them, and world, as the decoder gives them), the skinned
// mesh and the colour texture.
#ifndef FVV_PLAYER_EXPORT_EXPORTED_ACTOR_H_
#define FVV_PLAYER_EXPORT_EXPORTED_ACTOR_H_

#include <glm/gtc/quaternion.hpp>
#include <glm/mat4x4.hpp>
#include <string>
#include <vector>

#include "codec/base/status.h"
#include "container/body_model.h"
#include "fvv/fvv_export.h"

namespace fvv {

struct ExportedJoint {
  std::string name;
  int32_t parent = -1;  // an earlier joint; -1 for a root
  glm::vec3 rest_translation{0.0f};
  glm::quat rest_rotation{1, 0, 0, 0};
  RotationOrder order = RotationOrder::kZYX;
};

struct ExportedActor {
  std::vector<ExportedJoint> joints;
  double fps = 25;
  uint32_t first_frame = 0;
  // Per exported frame, per joint: the local transform T * R from the parent.
  std::vector<std::vector<glm::vec3>> translation;
  std::vector<std::vector<glm::quat>> rotation;
  // Per exported frame, per joint: the decoder's bone-to-world transform.
  std::vector<std::vector<glm::mat4>> world;

  std::vector<glm::mat4> inverse_bind;  // per joint: inverse of the rest world transform
  std::vector<float> positions, normals, uvs, weights;
  std::vector<uint16_t> skin_joints;
  std::vector<uint32_t> triangles;
  // Per exported frame: its surface (format version 12) less `positions`,
  // vertex_count x 3; empty when no exported frame has a surface.
  std::vector<std::vector<float>> surface_deltas;

  uint32_t texture_width = 0, texture_height = 0;
  std::vector<uint8_t> texture_rgb;  // row 0 at v = 0, as the atlas UVs
};

// Checks the settings against the stream (frames available, texture frame
// inside the range, texture size) and gathers the actor; the texture only when
// with_texture.
StatusOr<ExportedActor> GatherActor(fvv_decoder* decoder, const fvv_export_settings& settings,
                                    bool with_texture);

}  // namespace fvv

#endif  // FVV_PLAYER_EXPORT_EXPORTED_ACTOR_H_
