#include "encoder/body/kinematics.h"

#include <algorithm>
#include <cmath>

namespace fvv {

Eigen::Matrix3d EulerMatrix(RotationOrder order, const Eigen::Vector3d& angles) {
  const std::array<int, 3> axes = RotationOrderAxes(order);
  Eigen::Matrix3d r = Eigen::Matrix3d::Identity();
  for (int axis : axes) {
    r = r * Eigen::AngleAxisd(angles[axis], Eigen::Vector3d::Unit(axis)).toRotationMatrix();
  }
  return r;
}

Eigen::Vector3d MatrixToEuler(RotationOrder order, const Eigen::Matrix3d& r) {
  // R = R_i(a) R_j(b) R_k(c) for axes (i, j, k): a general Tait-Bryan decomposition.
  const std::array<int, 3> ax = RotationOrderAxes(order);
  const int i = ax[0], j = ax[1], k = ax[2];
  // Parity: +1 when (i, j, k) is a cyclic permutation of (0, 1, 2).
  const double sign = ((j - i + 3) % 3 == 1) ? 1.0 : -1.0;
  const double sb = std::clamp(sign * r(i, k), -1.0, 1.0);
  Eigen::Vector3d out;
  const double b = std::asin(sb);
  double a, c;
  if (std::abs(sb) < 1 - 1e-12) {
    a = std::atan2(-sign * r(j, k), r(k, k));
    c = std::atan2(-sign * r(i, j), r(i, i));
  } else {  // gimbal lock: put the whole remaining rotation into a
    a = std::atan2(sign * r(k, j), r(j, j));
    c = 0;
  }
  out[i] = a;
  out[j] = b;
  out[k] = c;
  return out;
}

std::vector<Affine> BoneWorldTransforms(const Skeleton& skeleton, const std::vector<double>& dofs) {
  const size_t n = skeleton.bones.size();
  std::vector<Eigen::Vector3d> angle(n, Eigen::Vector3d::Zero()), shift(n, Eigen::Vector3d::Zero());
  if (!dofs.empty()) {
    const std::vector<DofRef> refs = skeleton.Dofs();
    for (size_t d = 0; d < refs.size() && d < dofs.size(); ++d) {
      if (IsRotationDof(refs[d].kind)) {
        angle[refs[d].bone][refs[d].kind] = dofs[d];
      } else {
        shift[refs[d].bone][refs[d].kind - 3] = dofs[d];
      }
    }
  }
  std::vector<Affine> world(n);
  for (size_t b = 0; b < n; ++b) {
    const Bone& bone = skeleton.bones[b];
    const Eigen::Quaterniond rest(bone.rest_rotation[0], bone.rest_rotation[1],
                                  bone.rest_rotation[2], bone.rest_rotation[3]);
    Affine local = Affine::Identity();
    local.linear() = rest.normalized().toRotationMatrix() * EulerMatrix(bone.order, angle[b]);
    local.translation() = Eigen::Vector3d(bone.rest_translation[0], bone.rest_translation[1],
                                          bone.rest_translation[2]) +
                          shift[b];
    world[b] = bone.parent >= 0 ? world[bone.parent] * local : local;
  }
  return world;
}

std::vector<Eigen::Vector3d> JointPositions(const Skeleton& skeleton,
                                            const std::vector<double>& dofs) {
  std::vector<Eigen::Vector3d> out;
  for (const Affine& w : BoneWorldTransforms(skeleton, dofs)) out.push_back(w.translation());
  return out;
}

std::vector<Affine> SkinningMatrices(const Skeleton& skeleton, const std::vector<double>& dofs) {
  const std::vector<Affine> rest = BoneWorldTransforms(skeleton, {});
  std::vector<Affine> pose = BoneWorldTransforms(skeleton, dofs);
  for (size_t b = 0; b < pose.size(); ++b) pose[b] = pose[b] * rest[b].inverse();
  return pose;
}

std::vector<Eigen::Vector3f> SkinPositions(const Mesh& mesh, const std::vector<Affine>& skinning,
                                           std::vector<Eigen::Vector3f>* normals) {
  std::vector<Eigen::Vector3f> out(mesh.positions.size());
  if (normals) normals->resize(mesh.positions.size());
  for (size_t v = 0; v < mesh.positions.size(); ++v) {
    Eigen::Matrix4d m = Eigen::Matrix4d::Zero();
    for (int k = 0; k < kMaxInfluences; ++k) {
      if (mesh.weights[v][k] == 0 || mesh.joints[v][k] >= skinning.size()) continue;
      m += (mesh.weights[v][k] / 65535.0) * skinning[mesh.joints[v][k]].matrix();
    }
    const Eigen::Vector3d p(mesh.positions[v][0], mesh.positions[v][1], mesh.positions[v][2]);
    out[v] = (m.topLeftCorner<3, 3>() * p + m.topRightCorner<3, 1>()).cast<float>();
    if (normals && v < mesh.normals.size()) {
      const Eigen::Vector3d n(mesh.normals[v][0], mesh.normals[v][1], mesh.normals[v][2]);
      (*normals)[v] = (m.topLeftCorner<3, 3>() * n).normalized().cast<float>();
    }
  }
  return out;
}

int DofIndex(const Skeleton& skeleton, int bone, int kind) {
  const std::vector<DofRef> refs = skeleton.Dofs();
  for (size_t d = 0; d < refs.size(); ++d) {
    if (refs[d].bone == bone && refs[d].kind == kind) return static_cast<int>(d);
  }
  return -1;
}

std::vector<double> ClampToLimits(const Skeleton& skeleton, std::vector<double> dofs) {
  const std::vector<DofRef> refs = skeleton.Dofs();
  for (size_t d = 0; d < refs.size() && d < dofs.size(); ++d) {
    const Bone& bone = skeleton.bones[refs[d].bone];
    dofs[d] =
        std::clamp(dofs[d], double(bone.dof_min[refs[d].kind]), double(bone.dof_max[refs[d].kind]));
  }
  return dofs;
}

}  // namespace fvv
