// The body model carried by the 'modl' box (SPEC.md 3.3): a skeleton whose
// bones have degrees of freedom (what the motion track animates) and a skinned,
// textured triangle mesh.
#ifndef FVV_CONTAINER_BODY_MODEL_H_
#define FVV_CONTAINER_BODY_MODEL_H_

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "codec/base/status.h"
#include "container/box.h"
#include "container/file_header.h"
#include "container/model_quantisation.h"

namespace fvv {

// Euler rotation orders. kZYX means R = Rz * Ry * Rx (the first-named axis is the
// leftmost factor; applied to column vectors, X acts first), as in BVH channel lists.
enum class RotationOrder : uint8_t { kXYZ = 0, kXZY = 1, kYXZ = 2, kYZX = 3, kZXY = 4, kZYX = 5 };
constexpr int kRotationOrderCount = 6;
// Axis indices (0 = x, 1 = y, 2 = z) of an order, leftmost factor first.
std::array<int, 3> RotationOrderAxes(RotationOrder order);

// Degree-of-freedom bits of a bone, in the order their values are listed.
enum Dof : uint8_t {
  kDofRotX = 1 << 0,
  kDofRotY = 1 << 1,
  kDofRotZ = 1 << 2,
  kDofTransX = 1 << 3,
  kDofTransY = 1 << 4,
  kDofTransZ = 1 << 5,
};
constexpr int kDofKinds = 6;
inline bool IsRotationDof(int kind) { return kind < 3; }

struct Bone {
  std::string name;
  int32_t parent = -1;                             // index of an earlier bone; -1 for a root
  std::array<float, 3> rest_translation{};         // from the parent joint, metres
  std::array<float, 4> rest_rotation{1, 0, 0, 0};  // unit quaternion w, x, y, z
  RotationOrder order = RotationOrder::kZYX;
  uint8_t dof_mask = 0;
  // Limits of each DOF kind (radians for rotations, metres for translations);
  // only the entries of DOFs in dof_mask are stored.
  std::array<float, kDofKinds> dof_min{}, dof_max{};
};

// One animatable degree of freedom: the skeleton's DOFs listed bone by bone,
// and within a bone in Dof bit order. The motion track's value vectors follow it.
struct DofRef {
  uint16_t bone;
  uint8_t kind;  // 0..5 as the Dof bits
};

struct Skeleton {
  std::vector<Bone> bones;
  std::vector<DofRef> Dofs() const;
};

constexpr int kMaxInfluences = 4;

struct Mesh {
  std::vector<std::array<float, 3>> positions;  // metres, bind pose
  std::vector<std::array<float, 3>> normals;    // unit length
  std::vector<std::array<float, 2>> uvs;        // atlas coordinates in [0, 1]
  // Up to four skin influences per vertex; weights in units of 1/65535 that sum
  // to 65535 (exact integers, so every decoder skins with the same weights).
  std::vector<std::array<uint16_t, kMaxInfluences>> joints;
  std::vector<std::array<uint16_t, kMaxInfluences>> weights;
  std::vector<uint8_t> segments;  // body segment id per vertex
  std::vector<std::array<uint32_t, 3>> triangles;
};

struct BodyModel {
  Skeleton skeleton;
  Mesh mesh;
  // How the 'modl' box stores the mesh: as floats (version 0) or on a grid
  // (version 1), which the mesh's values then lie on (QuantiseModel).
  ModelQuantisation quantisation;
};

// Structural checks shared by writer and reader (parents, limits, indices,
// weights, array sizes). `limits` may be null (no level limits).
Status ValidateBodyModel(const BodyModel& model, const LevelLimits* limits);

// How 'modl' stores its model data (SPEC.md 3.3): as it is, or one zstd frame.
constexpr uint8_t kCompressionNone = 0;
constexpr uint8_t kCompressionZstd = 1;

// Version 1 when model.quantisation says so (the mesh's values taken to the
// nearest point of its grid), else version 0. The writer is body_model_enc.cc,
// in the encoder's container library.
std::vector<uint8_t> WriteModelBox(const BodyModel& model);
Status ReadModel(const BoxHeader& box, const uint8_t* payload, const LevelLimits& limits,
                 BodyModel* model);

}  // namespace fvv

#endif  // FVV_CONTAINER_BODY_MODEL_H_
