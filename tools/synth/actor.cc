#include "tools/synth/actor.h"

#include "encoder/body/kinematics.h"

namespace fvv {

std::vector<Eigen::Vector3f> Actor::PosedPositions(uint32_t frame) const {
  const ActorMesh& m = mesh();
  const std::vector<Eigen::Matrix4f> skin = Skinning(frame);
  const std::vector<Eigen::Vector3f>& bind = BindPositions(frame);
  std::vector<Eigen::Vector3f> out(m.positions.size());
  for (size_t v = 0; v < m.positions.size(); ++v) {
    Eigen::Matrix4f s = Eigen::Matrix4f::Zero();
    for (int k = 0; k < 4; ++k) {
      if (m.weights[v][k] > 0 && m.joints[v][k] < skin.size())
        s += m.weights[v][k] * skin[m.joints[v][k]];
    }
    out[v] = s.topLeftCorner<3, 3>() * bind[v] + s.topRightCorner<3, 1>();
  }
  return out;
}

BodyModelActor::BodyModelActor(BodyModel model, std::vector<std::vector<double>> poses,
                               Image texture, std::string description)
    : model_(std::move(model)), poses_(std::move(poses)), description_(std::move(description)) {
  const Mesh& m = model_.mesh;
  for (size_t v = 0; v < m.positions.size(); ++v) {
    mesh_.positions.emplace_back(m.positions[v][0], m.positions[v][1], m.positions[v][2]);
    mesh_.normals.emplace_back(m.normals[v][0], m.normals[v][1], m.normals[v][2]);
    mesh_.uvs.emplace_back(m.uvs[v][0], m.uvs[v][1]);
    mesh_.joints.push_back(m.joints[v]);
    Eigen::Vector4f w;
    for (int k = 0; k < 4; ++k) w[k] = m.weights[v][k] / 65535.0f;
    mesh_.weights.push_back(w);
  }
  for (const auto& t : m.triangles) mesh_.indices.insert(mesh_.indices.end(), t.begin(), t.end());
  mesh_.texture = std::move(texture);
}

std::vector<Eigen::Matrix4f> BodyModelActor::Skinning(uint32_t frame) const {
  std::vector<Eigen::Matrix4f> out;
  for (const Affine& a : SkinningMatrices(model_.skeleton, poses_[frame])) {
    out.push_back(a.matrix().cast<float>());
  }
  return out;
}

std::vector<NamedPoint> BodyModelActor::Joints(uint32_t frame) const {
  const std::vector<Eigen::Vector3d> p = JointPositions(model_.skeleton, poses_[frame]);
  std::vector<NamedPoint> out;
  for (size_t b = 0; b < p.size(); ++b) out.push_back({model_.skeleton.bones[b].name, p[b]});
  return out;
}

Eigen::Vector3d BodyModelActor::RootPosition(uint32_t frame) const {
  return BoneWorldTransforms(model_.skeleton, poses_[frame])[0].translation();
}

}  // namespace fvv
