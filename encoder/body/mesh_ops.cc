#include "encoder/body/mesh_ops.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <map>
#include <tuple>

namespace fvv {

std::vector<uint32_t> WeldVertices(const std::vector<Eigen::Vector3f>& positions) {
  std::map<std::tuple<float, float, float>, uint32_t> first;
  std::vector<uint32_t> welded(positions.size());
  for (size_t v = 0; v < positions.size(); ++v) {
    const auto key = std::make_tuple(positions[v].x(), positions[v].y(), positions[v].z());
    welded[v] = first.emplace(key, uint32_t(v)).first->second;
  }
  return welded;
}

std::vector<Eigen::Vector3f> VertexNormals(const std::vector<std::array<uint32_t, 3>>& triangles,
                                           const std::vector<Eigen::Vector3f>& positions,
                                           const std::vector<uint32_t>& welded) {
  std::vector<Eigen::Vector3d> sum(positions.size(), Eigen::Vector3d::Zero());
  for (const auto& t : triangles) {
    const Eigen::Vector3d a = positions[t[0]].cast<double>();
    const Eigen::Vector3d n =
        (positions[t[1]].cast<double>() - a).cross(positions[t[2]].cast<double>() - a);
    for (uint32_t i : t) sum[welded[i]] += n;
  }
  std::vector<Eigen::Vector3f> normals(positions.size());
  for (size_t v = 0; v < positions.size(); ++v) {
    const Eigen::Vector3d& n = sum[welded[v]];
    normals[v] = n.squaredNorm() > 0 ? n.normalized().cast<float>() : Eigen::Vector3f(0, 0, 1);
  }
  return normals;
}

std::vector<std::vector<uint32_t>> VertexNeighbours(
    const std::vector<std::array<uint32_t, 3>>& triangles, const std::vector<uint32_t>& welded) {
  std::vector<std::vector<uint32_t>> ring(welded.size());
  for (const auto& t : triangles) {
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = welded[t[k]], b = welded[t[(k + 1) % 3]];
      if (a == b) continue;
      ring[a].push_back(b);
      ring[b].push_back(a);
    }
  }
  for (auto& r : ring) {
    std::sort(r.begin(), r.end());
    r.erase(std::unique(r.begin(), r.end()), r.end());
  }
  return ring;
}

std::vector<Eigen::Vector3f> MeshPositions(const Mesh& mesh) {
  std::vector<Eigen::Vector3f> out;
  out.reserve(mesh.positions.size());
  for (const auto& p : mesh.positions) out.emplace_back(p[0], p[1], p[2]);
  return out;
}

std::vector<Eigen::Vector3f> MeshNormals(const Mesh& mesh) {
  std::vector<Eigen::Vector3f> out;
  out.reserve(mesh.normals.size());
  for (const auto& n : mesh.normals) out.emplace_back(n[0], n[1], n[2]);
  return out;
}

void SetMeshPositions(const std::vector<Eigen::Vector3f>& positions, Mesh* mesh) {
  const std::vector<uint32_t> welded = WeldVertices(MeshPositions(*mesh));
  const std::vector<Eigen::Vector3f> normals = VertexNormals(mesh->triangles, positions, welded);
  for (size_t v = 0; v < positions.size(); ++v) {
    mesh->positions[v] = {positions[v].x(), positions[v].y(), positions[v].z()};
    mesh->normals[v] = {normals[v].x(), normals[v].y(), normals[v].z()};
  }
}

}  // namespace fvv
