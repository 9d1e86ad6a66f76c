#include "encoder/track/feature_registration.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <optional>

#include "encoder/body/kinematics.h"

namespace fvv {
namespace {

// A fitted proportion: one scale shared by the listed segments' lengths (or
// girths).
struct ShapeParam {
  std::vector<int> segments;
  bool girth;
};

const std::vector<ShapeParam>& ShapeParams() {
  static const std::vector<ShapeParam> params = {
      {{kSegPelvis}, false},
      {{kSegAbdomen}, false},
      {{kSegChest}, false},
      {{kSegHead}, false},
      {{kSegLeftUpperArm, kSegRightUpperArm}, false},
      {{kSegLeftForearm, kSegRightForearm}, false},
      {{kSegLeftThigh, kSegRightThigh}, false},
      {{kSegLeftShank, kSegRightShank}, false},
      {{kSegPelvis}, true},  // hip width
      {{kSegChest}, true},   // shoulder width
  };
  return params;
}

double GetScale(const BodyShape& s, const ShapeParam& p) {
  return p.girth ? s.girth[p.segments[0]] : s.length[p.segments[0]];
}
void SetScale(double v, const ShapeParam& p, BodyShape* s) {
  for (int seg : p.segments) (p.girth ? s->girth : s->length)[seg] = v;
}

int JointIndex(const Skeleton& skeleton, const std::string& name) {
  for (size_t b = 0; b < skeleton.bones.size(); ++b) {
    if (skeleton.bones[b].name == name) return int(b);
  }
  return -1;
}

// The rotation taking the vectors `from` onto `to` best (Kabsch); with one
// pair, the smallest such rotation.
Eigen::Matrix3d BestRotation(const std::vector<Eigen::Vector3d>& from,
                             const std::vector<Eigen::Vector3d>& to) {
  if (from.size() == 1) {
    return Eigen::Quaterniond::FromTwoVectors(from[0], to[0]).toRotationMatrix();
  }
  Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
  for (size_t i = 0; i < from.size(); ++i) h += from[i] * to[i].transpose();
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(h, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
  d(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ? -1 : 1;
  return svd.matrixV() * d * svd.matrixU().transpose();
}

// Sets a bone's rotation DOFs from Euler angles (those its mask has), within limits.
void SetRotation(const Skeleton& skeleton, int bone, const Eigen::Vector3d& euler,
                 std::vector<double>* dofs) {
  const std::vector<DofRef> refs = skeleton.Dofs();
  const Bone& b = skeleton.bones[bone];
  for (size_t d = 0; d < refs.size(); ++d) {
    if (refs[d].bone != bone || !IsRotationDof(refs[d].kind)) continue;
    (*dofs)[d] = std::clamp(euler[refs[d].kind], double(b.dof_min[refs[d].kind]),
                            double(b.dof_max[refs[d].kind]));
  }
}

void ShiftRoot(const Skeleton& skeleton, const Eigen::Vector3d& t, std::vector<double>* dofs) {
  const std::vector<DofRef> refs = skeleton.Dofs();
  for (size_t d = 0; d < refs.size(); ++d) {
    if (refs[d].bone == 0 && !IsRotationDof(refs[d].kind)) (*dofs)[d] += t[refs[d].kind - 3];
  }
}

}  // namespace

std::vector<double> InitialisePose(const Skeleton& skeleton,
                                   const std::map<std::string, Feature3D>& features) {
  const size_t n = skeleton.bones.size();
  std::vector<double> dofs(skeleton.Dofs().size(), 0.0);
  std::vector<std::optional<Eigen::Vector3d>> observed(n);
  for (const auto& [name, f] : features) {
    const int j = JointIndex(skeleton, name);
    if (j >= 0) observed[j] = f.position;
  }
  std::vector<std::vector<int>> children(n);
  for (size_t b = 1; b < n; ++b) children[skeleton.bones[b].parent].push_back(int(b));
  // The trunk joints the root's orientation is fitted to: its descendants
  // down to the shoulders and hips.
  std::vector<int> trunk;
  for (const char* name :
       {"lumbar", "thoracic", "neck", "l_hip", "r_hip", "l_shoulder", "r_shoulder", "head"}) {
    const int j = JointIndex(skeleton, name);
    if (j >= 0) trunk.push_back(j);
  }
  // Places the root: its own observed position, or the observed trunk
  // joints' centroid matched.
  const auto place_root = [&] {
    const std::vector<Eigen::Vector3d> pos = JointPositions(skeleton, dofs);
    if (observed[0]) {
      ShiftRoot(skeleton, *observed[0] - pos[0], &dofs);
      return;
    }
    Eigen::Vector3d a = Eigen::Vector3d::Zero(), b = Eigen::Vector3d::Zero();
    int count = 0;
    for (int j : trunk) {
      if (!observed[j]) continue;
      a += pos[j];
      b += *observed[j];
      ++count;
    }
    if (count) ShiftRoot(skeleton, (b - a) / count, &dofs);
  };
  place_root();
  for (int pass = 0; pass < 2; ++pass) {
    for (size_t b = 0; b < n; ++b) {
      const std::vector<Affine> world = BoneWorldTransforms(skeleton, dofs);
      const Eigen::Vector3d origin = world[b].translation();
      std::vector<Eigen::Vector3d> from, to;
      const std::vector<int>& targets = b == 0 ? trunk : children[b];
      for (int c : targets) {
        if (!observed[c]) continue;
        const Eigen::Vector3d u = world[c].translation() - origin, v = *observed[c] - origin;
        if (u.norm() < 1e-6 || v.norm() < 1e-6) continue;
        // Directions only: the proportions may not fit yet.
        from.push_back(u.normalized());
        to.push_back(v.normalized());
      }
      if (from.empty()) continue;
      const Eigen::Matrix3d q = BestRotation(from, to);
      Eigen::Matrix3d parent = Eigen::Matrix3d::Identity();
      if (skeleton.bones[b].parent >= 0) parent = world[skeleton.bones[b].parent].linear();
      const Eigen::Matrix3d local = parent.transpose() * q * world[b].linear();
      SetRotation(skeleton, int(b), MatrixToEuler(skeleton.bones[b].order, local), &dofs);
      if (b == 0) place_root();
    }
  }
  return dofs;
}

StatusOr<Registration> RegisterSkeleton(const std::map<std::string, Feature3D>& features,
                                        const BodyShape& start, const std::vector<double>& initial,
                                        const RegistrationOptions& o) {
  FVV_RETURN_IF_ERROR(ValidateBodyShape(start));
  const Skeleton start_skeleton = MakeGenericSkeleton(start);
  std::vector<std::pair<int, Eigen::Vector3d>> targets;
  for (const auto& [name, f] : features) {
    const int j = JointIndex(start_skeleton, name);
    if (j < 0) return InvalidArgument("registration: \"" + name + "\" is not a joint");
    targets.emplace_back(j, f.position);
  }
  if (targets.size() < 4) {
    return InvalidArgument("registration: " + std::to_string(targets.size()) +
                           " joints observed; at least 4 are needed");
  }
  const size_t nd = start_skeleton.Dofs().size();
  if (!initial.empty() && initial.size() != nd) {
    return InvalidArgument("registration: the initial pose has " + std::to_string(initial.size()) +
                           " values, not " + std::to_string(nd));
  }
  const std::vector<ShapeParam>& params = ShapeParams();
  const size_t ns = o.fit_shape ? params.size() : 0;
  Registration out;
  out.joints = int(targets.size());

  // Proportions to start from: the start shape scaled by the observed bone
  // lengths' mean ratio to the model's (one factor: a first guess of size).
  BodyShape shape = start;
  if (o.fit_shape) {
    const std::vector<Eigen::Vector3d> rest = JointPositions(start_skeleton, {});
    double ratio = 0;
    int count = 0;
    for (const auto& [a, pa] : targets) {
      const int parent = start_skeleton.bones[a].parent;
      for (const auto& [b, pb] : targets) {
        if (b != parent) continue;
        const double model = (rest[a] - rest[b]).norm();
        if (model > 0.05) ratio += (pa - pb).norm() / model, ++count;
      }
    }
    if (count) {
      const double k = std::clamp(ratio / count, 0.6, 1.6);
      for (const ShapeParam& p : params)
        SetScale(std::clamp(GetScale(start, p) * k, 0.5, 2.0), p, &shape);
    }
  }
  std::vector<double> dofs =
      initial.empty() ? InitialisePose(MakeGenericSkeleton(shape), features) : initial;

  // Parameters: the DOFs, then the shape scales.
  Eigen::VectorXd x(nd + ns), lo(nd + ns), hi(nd + ns);
  const std::vector<DofRef> refs = start_skeleton.Dofs();
  for (size_t d = 0; d < nd; ++d) {
    const Bone& b = start_skeleton.bones[refs[d].bone];
    x[d] = dofs[d];
    lo[d] = b.dof_min[refs[d].kind];
    hi[d] = b.dof_max[refs[d].kind];
  }
  for (size_t p = 0; p < ns; ++p) {
    x[nd + p] = GetScale(shape, params[p]);
    lo[nd + p] = 0.5;
    hi[nd + p] = 2.0;
  }
  const auto shape_of = [&](const Eigen::VectorXd& v) {
    BodyShape s = start;
    for (size_t p = 0; p < ns; ++p) SetScale(v[nd + p], params[p], &s);
    return s;
  };
  const auto residuals = [&](const Eigen::VectorXd& v) {
    const BodyShape s = shape_of(v);
    const std::vector<double> d(v.data(), v.data() + nd);
    const std::vector<Eigen::Vector3d> pos = JointPositions(MakeGenericSkeleton(s), d);
    Eigen::VectorXd r(3 * targets.size() + ns);
    for (size_t i = 0; i < targets.size(); ++i) {
      r.segment<3>(3 * i) = pos[targets[i].first] - targets[i].second;
    }
    for (size_t p = 0; p < ns; ++p) {
      r[3 * targets.size() + p] =
          std::sqrt(o.shape_prior) * (v[nd + p] - GetScale(start, params[p]));
    }
    return r;
  };
  const auto joint_rms = [&](const Eigen::VectorXd& r) {
    return std::sqrt(r.head(3 * targets.size()).squaredNorm() / double(targets.size()));
  };
  Eigen::VectorXd r = residuals(x);
  out.initial_rms_m = joint_rms(r);
  double lambda = 1e-3;
  for (int it = 0; it < o.iterations; ++it) {
    // Forward-difference Jacobian; steps taken inward at an upper bound.
    Eigen::MatrixXd jac(r.size(), x.size());
    for (Eigen::Index k = 0; k < x.size(); ++k) {
      Eigen::VectorXd xp = x;
      const double h = x[k] + 1e-6 <= hi[k] ? 1e-6 : -1e-6;
      xp[k] += h;
      jac.col(k) = (residuals(xp) - r) / h;
    }
    const Eigen::VectorXd g = jac.transpose() * r;
    // Bound-constrained: a parameter at a bound the gradient pushes against
    // is held there this step.
    std::vector<Eigen::Index> free;
    for (Eigen::Index k = 0; k < x.size(); ++k) {
      const bool at_lo = x[k] <= lo[k] + 1e-12 && g[k] > 0;
      const bool at_hi = x[k] >= hi[k] - 1e-12 && g[k] < 0;
      if (!at_lo && !at_hi) free.push_back(k);
    }
    if (free.empty()) break;
    Eigen::MatrixXd jf(r.size(), Eigen::Index(free.size()));
    for (size_t i = 0; i < free.size(); ++i) jf.col(Eigen::Index(i)) = jac.col(free[i]);
    const Eigen::MatrixXd h = jf.transpose() * jf;
    const Eigen::VectorXd gf = jf.transpose() * r;
    bool improved = false;
    for (int tries = 0; tries < 10 && !improved; ++tries) {
      Eigen::MatrixXd a = h;
      a.diagonal() += lambda * (h.diagonal().array() + 1e-9).matrix();
      const Eigen::VectorXd step = a.ldlt().solve(-gf);
      Eigen::VectorXd next = x;
      for (size_t i = 0; i < free.size(); ++i) {
        next[free[i]] = std::clamp(x[free[i]] + step[Eigen::Index(i)], lo[free[i]], hi[free[i]]);
      }
      const Eigen::VectorXd rn = residuals(next);
      if (rn.squaredNorm() < r.squaredNorm()) {
        const double gain = r.squaredNorm() - rn.squaredNorm();
        x = next;
        r = rn;
        lambda = std::max(lambda / 3, 1e-9);
        improved = true;
        if (gain < 1e-14) it = o.iterations;  // converged
      } else {
        lambda *= 4;
      }
    }
    if (!improved) break;
  }
  out.dofs.assign(x.data(), x.data() + nd);
  out.shape = shape_of(x);
  out.rms_m = joint_rms(r);
  return out;
}

}  // namespace fvv
