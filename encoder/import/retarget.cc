#include "encoder/import/retarget.h"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "encoder/body/generic_body.h"
#include "encoder/body/kinematics.h"

namespace fvv {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;

// BVH joint names that drive each generic bone, tried in order (CMU first, then
// common MotionBuilder / Mixamo / 3ds Max names). The BVH joint's rotation
// moves the segment from it to its child, as the generic bone moves its segment.
const std::vector<std::vector<std::string>>& Candidates() {
  static const std::vector<std::vector<std::string>> k = {
      {"Hips", "hip", "pelvis", "Root"},                                 // root
      {"Spine", "LowerBack", "abdomen", "Spine1", "Chest"},              // lumbar
      {"Spine1", "Spine2", "chest", "Chest", "Spine"},                   // thoracic
      {"Neck", "neck", "Neck1"},                                         // neck
      {"Head", "head"},                                                  // head
      {"LeftArm", "LeftShoulder", "lShldr", "LeftUpArm", "l_upperarm"},  // left shoulder
      {"LeftForeArm", "lForeArm", "LeftLowArm", "LeftElbow"},
      {"LeftHand", "lHand", "LeftWrist"},
      {"RightArm", "RightShoulder", "rShldr", "RightUpArm", "r_upperarm"},
      {"RightForeArm", "rForeArm", "RightLowArm", "RightElbow"},
      {"RightHand", "rHand", "RightWrist"},
      {"LeftUpLeg", "lThigh", "LeftHip", "LeftUpperLeg"},
      {"LeftLeg", "lShin", "LeftKnee", "LeftLowLeg", "LeftLowerLeg"},
      {"LeftFoot", "lFoot", "LeftAnkle"},
      {"RightUpLeg", "rThigh", "RightHip", "RightUpperLeg"},
      {"RightLeg", "rShin", "RightKnee", "RightLowLeg", "RightLowerLeg"},
      {"RightFoot", "rFoot", "RightAnkle"},
  };
  return k;
}

std::string Lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

int FindBone(const Skeleton& s, const std::vector<std::string>& names) {
  for (const std::string& n : names) {
    for (size_t b = 0; b < s.bones.size(); ++b) {
      if (Lower(s.bones[b].name) == Lower(n)) return static_cast<int>(b);
    }
  }
  return -1;
}

// The rest direction of the segment a bone moves: towards its first descendant
// at a non-zero offset (CMU hands have a zero-length FingerBase first); zero
// when it has none (a head with only an End Site).
Vector3d RestSegmentDirection(const Skeleton& s, const std::vector<Vector3d>& rest, int bone) {
  std::vector<int> frontier = {bone};
  while (!frontier.empty()) {
    std::vector<int> next;
    for (size_t c = 0; c < s.bones.size(); ++c) {
      if (std::find(frontier.begin(), frontier.end(), s.bones[c].parent) == frontier.end())
        continue;
      const Vector3d d = rest[c] - rest[bone];
      if (d.norm() > 1e-6) return d.normalized();
      next.push_back(static_cast<int>(c));
    }
    frontier = next;
  }
  return Vector3d::Zero();
}

// The rotation taking unit vector a onto unit vector b by the shortest arc.
Matrix3d Align(const Vector3d& a, const Vector3d& b) {
  if (a.norm() < 0.5 || b.norm() < 0.5) return Matrix3d::Identity();
  return Eigen::Quaterniond::FromTwoVectors(a, b).toRotationMatrix();
}

// The Euler angles for `bone` (only its DOFs, within limits) whose world
// rotation parent * R best matches `target`: mostly by where it points the
// segment (rest direction `e` onto target * e), a little by the full rotation
// (twist). Gauss-Newton from the plain Euler projection; a joint with all three
// rotation DOFs reproduces `target` exactly.
Vector3d FitAngles(const Bone& bone, const Matrix3d& parent, const Matrix3d& target,
                   const Vector3d& e) {
  const Matrix3d local = parent.transpose() * target;
  Vector3d angles = MatrixToEuler(bone.order, local);
  std::vector<int> free;
  for (int k = 0; k < 3; ++k) {
    if (bone.dof_mask & (1u << k)) {
      free.push_back(k);
    } else {
      angles[k] = 0;
    }
    angles[k] = std::clamp(angles[k], double(bone.dof_min[k]), double(bone.dof_max[k]));
  }
  if (free.size() == 3 || free.empty()) return angles;
  const Vector3d want = local * e;
  auto residual = [&](const Vector3d& a) {
    const Matrix3d r = EulerMatrix(bone.order, a);
    Eigen::Matrix<double, 12, 1> out;
    out.head<3>() = 4.0 * (r * e - want);  // direction dominates
    Eigen::Map<Eigen::Matrix<double, 9, 1>>(out.data() + 3) =
        0.3 * Eigen::Map<const Eigen::Matrix<double, 9, 1>>(Matrix3d(r - local).data());
    return out;
  };
  for (int it = 0; it < 12; ++it) {
    const auto r0 = residual(angles);
    Eigen::MatrixXd j(12, free.size());
    for (size_t c = 0; c < free.size(); ++c) {
      Vector3d a = angles;
      a[free[c]] += 1e-6;
      j.col(c) = (residual(a) - r0) / 1e-6;
    }
    const Eigen::VectorXd step =
        (j.transpose() * j + 1e-9 * Eigen::MatrixXd::Identity(free.size(), free.size()))
            .ldlt()
            .solve(-j.transpose() * r0);
    for (size_t c = 0; c < free.size(); ++c) {
      const int k = free[c];
      angles[k] = std::clamp(angles[k] + step[c], double(bone.dof_min[k]), double(bone.dof_max[k]));
    }
    if (step.norm() < 1e-10) break;
  }
  return angles;
}

// Shoulders and hips carry a hinge (elbow, knee) below them: a hinge can only
// bend in one plane, so the upper bone's twist is chosen to put that plane
// through the mocap limb (upper direction d1 and lower direction d2), rather
// than copied from the mocap skeleton, whose hinge axis may differ. Nearly
// straight limbs keep the mocap twist (the plane is undefined there).
Matrix3d HingePlaneRotation(const Matrix3d& mocap, const Vector3d& e1, const Vector3d& hinge,
                            const Vector3d& d1, const Vector3d& d2) {
  const Vector3d bend = d1.cross(d2);
  const Vector3d from_mocap = (mocap * hinge - d1 * d1.dot(mocap * hinge)).normalized();
  const double s = bend.norm();
  const double t = std::clamp((s - 0.09) / (0.34 - 0.09), 0.0, 1.0);  // sin 5 .. 20 degrees
  const double w = t * t * (3 - 2 * t);
  Vector3d n = w * (s > 1e-12 ? Vector3d(bend / s) : from_mocap) + (1 - w) * from_mocap;
  n = (n - d1 * d1.dot(n));
  if (n.norm() < 1e-9) return mocap;
  n.normalize();
  Matrix3d from, to;
  from << e1, hinge, e1.cross(hinge);
  to << d1, n, d1.cross(n);
  return to * from.transpose();
}

}  // namespace

StatusOr<std::vector<std::vector<double>>> RetargetToGenericBody(const BvhMotion& bvh,
                                                                 const Skeleton& generic,
                                                                 const RetargetOptions& o) {
  if (generic.bones.size() != kGenericJointCount) {
    return InvalidArgument("retarget: the target is not the generic body model");
  }
  if (!(o.fps > 0) || !(o.start_seconds >= 0)) return InvalidArgument("retarget: bad fps or start");
  std::vector<int> map(kGenericJointCount);
  for (int g = 0; g < kGenericJointCount; ++g) {
    // The generic body's own joint names first: motion fvv exported (fvv export
    // -o motion.bvh) comes back onto the same joints.
    map[g] = FindBone(bvh.skeleton, {GenericJointName(g)});
    if (map[g] < 0) map[g] = FindBone(bvh.skeleton, Candidates()[g]);
    if (map[g] < 0) {
      std::string tried = GenericJointName(g);
      for (const std::string& n : Candidates()[g]) tried += ", " + n;
      return InvalidArgument(std::string("retarget: the BVH skeleton has no joint for ") +
                             GenericJointName(g) + " (looked for " + tried + ")");
    }
  }
  if (bvh.skeleton.bones[map[kRoot]].parent != -1) {
    return InvalidArgument("retarget: the BVH joint mapped to the root is not the BVH root");
  }

  // Rest geometry of both skeletons; the correction of each generic bone.
  const std::vector<Vector3d> bvh_rest = JointPositions(bvh.skeleton, {});
  const std::vector<Vector3d> gen_rest = JointPositions(generic, {});
  std::vector<Matrix3d> correction(kGenericJointCount, Matrix3d::Identity());
  for (int g = 1; g < kGenericJointCount; ++g) {
    Vector3d e = Vector3d::Zero();
    for (int c = 0; c < kGenericJointCount; ++c) {
      if (generic.bones[c].parent == g && (gen_rest[c] - gen_rest[g]).norm() > 1e-6) {
        e = (gen_rest[c] - gen_rest[g]).normalized();
        break;
      }
    }
    if (g == kLeftWrist || g == kRightWrist) e = Vector3d(g == kLeftWrist ? 1 : -1, 0, 0);
    if (g == kLeftAnkle || g == kRightAnkle) e = Vector3d(0, 0, 1);
    correction[g] = Align(e, RestSegmentDirection(bvh.skeleton, bvh_rest, map[g]));
  }
  // Leg length (hip to ankle) sets the scale of the root's path.
  const double bvh_leg = (bvh_rest[map[kLeftHip]] - bvh_rest[map[kLeftKnee]]).norm() +
                         (bvh_rest[map[kLeftKnee]] - bvh_rest[map[kLeftAnkle]]).norm();
  const double gen_leg = (gen_rest[kLeftHip] - gen_rest[kLeftKnee]).norm() +
                         (gen_rest[kLeftKnee] - gen_rest[kLeftAnkle]).norm();
  if (!(bvh_leg > 1e-9)) return InvalidArgument("retarget: the BVH skeleton's legs have no length");
  const double scale = gen_leg / bvh_leg;

  const std::vector<std::vector<double>> clip = ResampleMotion(bvh, o.fps, o.start_seconds);
  if (clip.empty()) {
    return InvalidArgument("retarget: the motion lasts less than the start time (" +
                           std::to_string(o.start_seconds) + " s)");
  }
  const size_t count = o.frames ? o.frames : clip.size();
  if (count > clip.size()) {
    return InvalidArgument("retarget: the motion holds " + std::to_string(clip.size()) +
                           " frames at " + std::to_string(o.fps) + " fps from the start time, " +
                           std::to_string(count) + " asked for");
  }

  // Rest direction of each generic bone's segment.
  std::vector<Vector3d> rest_dir(kGenericJointCount, Vector3d::UnitY());
  for (int g = 0; g < kGenericJointCount; ++g) {
    for (int c = 0; c < kGenericJointCount; ++c) {
      if (generic.bones[c].parent == g && (gen_rest[c] - gen_rest[g]).norm() > 1e-6) {
        rest_dir[g] = (gen_rest[c] - gen_rest[g]).normalized();
        break;
      }
    }
  }
  rest_dir[kLeftWrist] = Vector3d::UnitX();
  rest_dir[kRightWrist] = -Vector3d::UnitX();
  rest_dir[kLeftAnkle] = rest_dir[kRightAnkle] = Vector3d::UnitZ();
  // Hinges below shoulders and hips: the axis a positive flexion turns about.
  struct Hinge {
    int upper, lower;
    Vector3d axis;
  };
  const Hinge hinges[] = {{kLeftShoulder, kLeftElbow, -Vector3d::UnitY()},
                          {kRightShoulder, kRightElbow, Vector3d::UnitY()},
                          {kLeftHip, kLeftKnee, Vector3d::UnitX()},
                          {kRightHip, kRightKnee, Vector3d::UnitX()}};

  const std::vector<DofRef> refs = generic.Dofs();
  std::vector<std::vector<double>> out;
  for (size_t f = 0; f < count; ++f) {
    const std::vector<Affine> world = BoneWorldTransforms(bvh.skeleton, clip[f]);
    std::vector<Matrix3d> target(kGenericJointCount);
    for (int g = 0; g < kGenericJointCount; ++g) target[g] = world[map[g]].linear() * correction[g];
    for (const Hinge& h : hinges) {
      target[h.upper] = HingePlaneRotation(target[h.upper], rest_dir[h.upper], h.axis,
                                           target[h.upper] * rest_dir[h.upper],
                                           target[h.lower] * rest_dir[h.lower]);
    }
    std::vector<double> dofs(refs.size(), 0.0);
    std::vector<Matrix3d> achieved(kGenericJointCount);
    for (int g = 0; g < kGenericJointCount; ++g) {
      const Bone& bone = generic.bones[g];
      const Matrix3d parent = bone.parent >= 0 ? achieved[bone.parent] : Matrix3d::Identity();
      const Vector3d angles = FitAngles(bone, parent, target[g], rest_dir[g]);
      achieved[g] = parent * EulerMatrix(bone.order, angles);
      for (size_t d = 0; d < refs.size(); ++d) {
        if (refs[d].bone != g) continue;
        if (refs[d].kind < 3) {
          dofs[d] = angles[refs[d].kind];
        } else {
          const Vector3d p = world[map[kRoot]].translation() * scale;
          const int axis = refs[d].kind - 3;
          dofs[d] = p[axis] - bone.rest_translation[axis];
        }
      }
    }
    out.push_back(ClampToLimits(generic, dofs));
  }

  // Centre the path horizontally and put the lowest foot point of the clip on the floor.
  const int tx = DofIndex(generic, kRoot, 3), ty = DofIndex(generic, kRoot, 4),
            tz = DofIndex(generic, kRoot, 5);
  if (tx >= 0 && ty >= 0 && tz >= 0) {
    double mx = 0, mz = 0;
    for (const auto& f : out) mx += f[tx], mz += f[tz];
    mx /= out.size(), mz /= out.size();
    double lowest = 1e9;
    for (auto& f : out) {
      if (o.centre) f[tx] -= mx, f[tz] -= mz;
      const std::vector<Vector3d> j = JointPositions(generic, f);
      lowest = std::min({lowest, j[kLeftAnkle].y(), j[kRightAnkle].y()});
    }
    const double lift = gen_rest[kLeftAnkle].y() - lowest;  // ankle height standing
    for (auto& f : out) f[ty] += lift;
  }
  return out;
}

}  // namespace fvv
