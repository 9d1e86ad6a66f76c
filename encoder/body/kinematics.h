// Forward kinematics and linear-blend skinning in double precision, with the
// conventions of the motion track (SPEC.md 6.1): a bone's local transform is
// T(rest translation + DOF translation) * R(rest rotation) * R(Euler DOFs in the
// bone's order). Capture, tracking and the synthetic generator share it.
#ifndef FVV_ENCODER_BODY_KINEMATICS_H_
#define FVV_ENCODER_BODY_KINEMATICS_H_

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "container/body_model.h"

namespace fvv {

using Affine = Eigen::Transform<double, 3, Eigen::Isometry>;

// R = R(axis0, a0) * R(axis1, a1) * R(axis2, a2) for the order's axes, where
// `angles` holds the angles about X, Y and Z (radians).
Eigen::Matrix3d EulerMatrix(RotationOrder order, const Eigen::Vector3d& angles);
// The inverse of EulerMatrix (angles about X, Y and Z), the middle angle in
// [-pi/2, pi/2].
Eigen::Vector3d MatrixToEuler(RotationOrder order, const Eigen::Matrix3d& r);

// Bone world transforms for DOF values in Skeleton::Dofs() order (empty: rest pose).
std::vector<Affine> BoneWorldTransforms(const Skeleton& skeleton, const std::vector<double>& dofs);
// World position of every joint (bone origin).
std::vector<Eigen::Vector3d> JointPositions(const Skeleton& skeleton,
                                            const std::vector<double>& dofs);
// Per bone: world(pose) * world(rest)^-1, the matrices linear-blend skinning uses.
std::vector<Affine> SkinningMatrices(const Skeleton& skeleton, const std::vector<double>& dofs);
// Skinned vertex positions (and normals when `normals` is not null).
std::vector<Eigen::Vector3f> SkinPositions(const Mesh& mesh, const std::vector<Affine>& skinning,
                                           std::vector<Eigen::Vector3f>* normals = nullptr);

// Index of the DOF (bone, kind) in Skeleton::Dofs() order, or -1.
int DofIndex(const Skeleton& skeleton, int bone, int kind);

// Each value clamped into its DOF's limits.
std::vector<double> ClampToLimits(const Skeleton& skeleton, std::vector<double> dofs);

}  // namespace fvv

#endif  // FVV_ENCODER_BODY_KINEMATICS_H_
