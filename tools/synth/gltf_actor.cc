#include "tools/synth/gltf_actor.h"

#include <algorithm>

namespace fvv {

StatusOr<std::unique_ptr<GltfActor>> GltfActor::Load(const std::string& path, double fps,
                                                     uint32_t frames) {
  StatusOr<GltfCharacter> c = LoadGltf(path);
  if (!c.ok()) return c.status();
  std::unique_ptr<GltfActor> a(new GltfActor());
  a->character_ = std::move(*c);
  a->fps_ = fps;
  a->frames_ = frames;
  a->animation_ = a->character_.animations.empty() ? -1 : 0;
  const GltfCharacter& ch = a->character_;
  a->mesh_.positions = ch.positions;
  a->mesh_.normals = ch.normals;
  a->mesh_.uvs = ch.uvs;
  a->mesh_.joints = ch.joints;
  a->mesh_.weights = ch.weights;
  a->mesh_.indices = ch.indices;
  a->mesh_.texture = ch.texture;

  // Feet on the floor (the lowest vertex over the clip) and the root's mean
  // horizontal position at the centre of the capture volume.
  double lowest = 1e30;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  const uint32_t samples = std::min<uint32_t>(frames, 50);
  for (uint32_t i = 0; i < samples; ++i) {
    const uint32_t f = samples > 1 ? uint32_t(uint64_t(i) * (frames - 1) / (samples - 1)) : 0;
    for (const Eigen::Vector3f& p : a->PosedPositions(f)) lowest = std::min(lowest, double(p.y()));
    mean += a->RootPosition(f);
  }
  mean /= samples;
  a->placement_.topRightCorner<3, 1>() = Eigen::Vector3d(-mean.x(), -lowest, -mean.z());
  const size_t slash = path.find_last_of('/');
  a->description_ =
      "glTF character " + (slash == std::string::npos ? path : path.substr(slash + 1)) + " (" +
      std::to_string(ch.joint_nodes.size()) + " joints, " + std::to_string(ch.indices.size() / 3) +
      " triangles, " +
      (a->animation_ >= 0
           ? "animation " +
                 (ch.animations[0].name.empty() ? std::string("0")
                                                : "\"" + ch.animations[0].name + "\"") +
                 " looped"
           : std::string("no animation: rest pose")) +
      ")";
  return a;
}

std::vector<Eigen::Matrix4f> GltfActor::Skinning(uint32_t frame) const {
  std::vector<Eigen::Matrix4f> out;
  for (const Eigen::Matrix4d& m : character_.Skinning(animation_, Seconds(frame))) {
    out.push_back((placement_ * m).cast<float>());
  }
  return out;
}

std::vector<NamedPoint> GltfActor::Joints(uint32_t frame) const {
  const std::vector<Eigen::Matrix4d> world = character_.NodeWorld(animation_, Seconds(frame));
  std::vector<NamedPoint> out;
  for (int node : character_.joint_nodes) {
    const Eigen::Vector4d p = placement_ * world[node].col(3);
    out.push_back({character_.nodes[node].name, p.head<3>()});
  }
  return out;
}

Eigen::Vector3d GltfActor::RootPosition(uint32_t frame) const {
  const std::vector<Eigen::Matrix4d> world = character_.NodeWorld(animation_, Seconds(frame));
  const Eigen::Vector4d p = placement_ * world[character_.joint_nodes[0]].col(3);
  return p.head<3>();
}

}  // namespace fvv
