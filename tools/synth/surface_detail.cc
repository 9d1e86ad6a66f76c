#include "tools/synth/surface_detail.h"

#include <algorithm>
#include <cmath>
#include <random>

#include "encoder/body/mesh_ops.h"

namespace fvv {

void AddSurfaceDetail(double amplitude, uint32_t seed, BodyModel* model) {
  if (!(amplitude > 0)) return;
  Mesh& mesh = model->mesh;
  const std::vector<Eigen::Vector3f> positions = MeshPositions(mesh);
  if (positions.empty()) return;
  std::mt19937 rng(seed * 2654435761u + 17);
  std::uniform_int_distribution<size_t> pick(0, positions.size() - 1);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  struct Bump {
    Eigen::Vector3d centre;
    double height;
  };
  std::vector<Bump> bumps;
  constexpr int kBumps = 60;
  for (int k = 0; k < kBumps; ++k) {
    bumps.push_back({positions[pick(rng)].cast<double>(),
                     (unit(rng) < 0.5 ? -1 : 1) * (0.5 + 0.5 * unit(rng))});
  }
  constexpr double kRadius = 0.07;
  std::vector<Eigen::Vector3f> moved(positions.size());
  for (size_t v = 0; v < positions.size(); ++v) {
    const Eigen::Vector3d p = positions[v].cast<double>();
    double d = 0;
    for (const Bump& b : bumps) {
      d += b.height * std::exp(-(p - b.centre).squaredNorm() / (2 * kRadius * kRadius));
    }
    // Hollows half as deep as bumps are high: limbs stay limbs.
    d = amplitude * std::clamp(d, -0.5, 1.0);
    const Eigen::Vector3d n(mesh.normals[v][0], mesh.normals[v][1], mesh.normals[v][2]);
    moved[v] = (p + d * n).cast<float>();
  }
  SetMeshPositions(moved, &mesh);
}

}  // namespace fvv
