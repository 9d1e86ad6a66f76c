// Skinned, animated glTF 2.0 characters (tinygltf): the skinned mesh (every
// skinned primitive merged), its skin, base-colour textures and animations,
// evaluated at any time. `fvv synth --actor FILE.glb` films them, and the
// tracking benchmark uses them as bodies that are not our model.
#ifndef FVV_ENCODER_IMPORT_GLTF_H_
#define FVV_ENCODER_IMPORT_GLTF_H_

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <string>
#include <vector>

#include "codec/base/status.h"
#include "encoder/io/image_io.h"

namespace fvv {

struct GltfNode {
  std::string name;
  int parent = -1;
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d scale = Eigen::Vector3d::Ones();
  bool has_matrix = false;  // a fixed matrix instead of TRS (not animatable)
  Eigen::Matrix4d matrix = Eigen::Matrix4d::Identity();
};

struct GltfChannel {
  int node = -1;
  enum class Path { kTranslation, kRotation, kScale } path = Path::kTranslation;
  enum class Interpolation { kLinear, kStep, kCubicSpline } interpolation = Interpolation::kLinear;
  std::vector<float> times;  // seconds, increasing
  std::vector<float>
      values;  // 3 or 4 per key (x3 for cubic splines: in-tangent, value, out-tangent)
};

struct GltfAnimation {
  std::string name;
  double duration = 0;
  std::vector<GltfChannel> channels;
};

struct GltfCharacter {
  std::vector<Eigen::Vector3f> positions, normals;  // bind pose
  std::vector<Eigen::Vector2f> uvs;                 // v = 0 at the texture's top row
  std::vector<std::array<uint16_t, 4>> joints;      // indices into `joint_nodes`
  std::vector<Eigen::Vector4f> weights;             // sum to 1
  std::vector<uint32_t> indices;
  Image texture;  // RGB; several materials' textures are stacked vertically
  std::vector<GltfNode> nodes;
  std::vector<int> joint_nodes;               // the skin's joints
  std::vector<Eigen::Matrix4d> inverse_bind;  // per joint
  std::vector<GltfAnimation> animations;

  // World transforms of every node at `seconds` into `animation` (-1: rest);
  // times beyond the clip wrap around (animations loop).
  std::vector<Eigen::Matrix4d> NodeWorld(int animation, double seconds) const;
  // Per joint: world(joint) * inverse bind matrix.
  std::vector<Eigen::Matrix4d> Skinning(int animation, double seconds) const;
};

// Limits what a file may ask us to allocate: 4M vertices, 256 joints.
StatusOr<GltfCharacter> LoadGltf(const std::string& path);

}  // namespace fvv

#endif  // FVV_ENCODER_IMPORT_GLTF_H_
