#include "tools/synth/garment.h"

#include <algorithm>
#include <cmath>

#include "encoder/body/generic_body.h"
#include "encoder/body/kinematics.h"

namespace fvv {

std::vector<std::vector<Eigen::Vector3f>> GarmentPositions(
    const BodyModel& model, const std::vector<std::vector<double>>& poses, double amplitude) {
  const Mesh& mesh = model.mesh;
  const size_t n = mesh.positions.size();
  // Where the cloth is, in the bind pose: the pelvis, and the thighs down to
  // a third of their length above the knee.
  // The thighs' extent in the bind pose (y up): knee to hip.
  double knee_y = 1e9, hip_y = -1e9;
  for (size_t v = 0; v < n && v < mesh.segments.size(); ++v) {
    if (mesh.segments[v] == kSegLeftThigh || mesh.segments[v] == kSegRightThigh) {
      knee_y = std::min<double>(knee_y, mesh.positions[v][1]);
      hip_y = std::max<double>(hip_y, mesh.positions[v][1]);
    }
  }
  const std::vector<double> rest(model.skeleton.Dofs().size(), 0.0);
  const std::vector<Eigen::Vector3d> joints = JointPositions(model.skeleton, rest);
  std::vector<double> cloth(n, 0.0);
  for (size_t v = 0; v < n && v < mesh.segments.size(); ++v) {
    const int s = mesh.segments[v];
    if (s == kSegPelvis) {
      cloth[v] = 0.6;
    } else if (s == kSegLeftThigh || s == kSegRightThigh) {
      const double t = (mesh.positions[v][1] - knee_y) / std::max(1e-3, hip_y - knee_y);
      cloth[v] = std::clamp((t - 0.33) / 0.33, 0.0, 1.0);
    }
  }
  // The flare: a lagged response to how far the knees stand apart.
  const double rest_spread = (joints[kLeftKnee] - joints[kRightKnee]).norm();
  double flare = 0;
  std::vector<std::vector<Eigen::Vector3f>> out;
  for (size_t f = 0; f < poses.size(); ++f) {
    const std::vector<Eigen::Vector3d> j = JointPositions(model.skeleton, poses[f]);
    const double spread = std::max(0.0, (j[kLeftKnee] - j[kRightKnee]).norm() - rest_spread);
    const double target = std::min(1.0, spread / 0.25);
    flare = f == 0 ? target : flare + 0.35 * (target - flare);
    const double d = amplitude * (0.3 + 0.7 * flare);
    std::vector<Eigen::Vector3f> p(n);
    for (size_t v = 0; v < n; ++v) {
      const Eigen::Vector3f x(mesh.positions[v][0], mesh.positions[v][1], mesh.positions[v][2]);
      const Eigen::Vector3f nv(mesh.normals[v][0], mesh.normals[v][1], mesh.normals[v][2]);
      p[v] = x + float(d * cloth[v]) * nv;
    }
    out.push_back(std::move(p));
  }
  return out;
}

}  // namespace fvv
