// A glTF 2.0 character as an actor: its first animation (looped) sampled at the
// capture's frame rate, placed with its feet on the studio floor and its path
// centred in the capture volume.
#ifndef FVV_TOOLS_SYNTH_GLTF_ACTOR_H_
#define FVV_TOOLS_SYNTH_GLTF_ACTOR_H_

#include <memory>
#include <string>

#include "codec/base/status.h"
#include "encoder/import/gltf.h"
#include "tools/synth/actor.h"

namespace fvv {

class GltfActor : public Actor {
 public:
  static StatusOr<std::unique_ptr<GltfActor>> Load(const std::string& path, double fps,
                                                   uint32_t frames);
  std::string Describe() const override { return description_; }
  const ActorMesh& mesh() const override { return mesh_; }
  size_t bone_count() const override { return character_.joint_nodes.size(); }
  uint32_t frame_count() const override { return frames_; }
  std::vector<Eigen::Matrix4f> Skinning(uint32_t frame) const override;
  std::vector<NamedPoint> Joints(uint32_t frame) const override;
  Eigen::Vector3d RootPosition(uint32_t frame) const override;
  const GltfCharacter& character() const { return character_; }

 private:
  GltfActor() = default;
  double Seconds(uint32_t frame) const { return frame / fps_; }
  GltfCharacter character_;
  ActorMesh mesh_;
  Eigen::Matrix4d placement_ = Eigen::Matrix4d::Identity();
  double fps_ = 25;
  uint32_t frames_ = 0;
  int animation_ = -1;
  std::string description_;
};

}  // namespace fvv

#endif  // FVV_TOOLS_SYNTH_GLTF_ACTOR_H_
