#include "encoder/encode/mirror_texels.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "encoder/body/mesh_ops.h"

namespace fvv {
namespace {

uint64_t CellKey(int x, int y, int z) {
  constexpr int kBias = 1 << 20;  // cells of 2 cm: +-20 km
  return (uint64_t(uint32_t(x + kBias)) << 42) ^ (uint64_t(uint32_t(y + kBias)) << 21) ^
         uint64_t(uint32_t(z + kBias));
}

// A texel and its mirror face mirrored ways: their normals agree within
// about 45 degrees once one is mirrored (a limb's inner side and the torso
// beside it do not).
constexpr float kLeastNormalAgreement = 0.7f;

}  // namespace

std::vector<int32_t> MirrorTexels(const TexelMap& map, const Mesh& mesh, float max_distance) {
  const size_t n = map.texel.size();
  if (!(max_distance > 0)) return std::vector<int32_t>(n, -1);
  const std::vector<Eigen::Vector3f> positions = MeshPositions(mesh);
  const std::vector<Eigen::Vector3f> normals = MeshNormals(mesh);
  std::vector<Eigen::Vector3f> pos(n), nrm(n);
  for (size_t e = 0; e < n; ++e) {
    TexelSurfacePoint(map, mesh.triangles, positions, normals, e, &pos[e], &nrm[e]);
  }
  // Cells max_distance wide: the nearest within it lies in the 27 cells
  // around the mirrored point.
  auto cell = [&](float v) { return int(std::floor(v / max_distance)); };
  std::unordered_map<uint64_t, std::vector<int32_t>> grid;
  for (size_t e = 0; e < n; ++e) {
    grid[CellKey(cell(pos[e].x()), cell(pos[e].y()), cell(pos[e].z()))].push_back(int32_t(e));
  }
  std::vector<int32_t> mirror(n, -1);
  for (size_t e = 0; e < n; ++e) {
    if (std::abs(pos[e].x()) < max_distance) continue;
    const Eigen::Vector3f q(-pos[e].x(), pos[e].y(), pos[e].z());
    const Eigen::Vector3f qn(-nrm[e].x(), nrm[e].y(), nrm[e].z());
    float best = max_distance * max_distance;
    const int cx = cell(q.x()), cy = cell(q.y()), cz = cell(q.z());
    for (int dz = -1; dz <= 1; ++dz) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const auto it = grid.find(CellKey(cx + dx, cy + dy, cz + dz));
          if (it == grid.end()) continue;
          for (int32_t k : it->second) {
            const float d = (pos[size_t(k)] - q).squaredNorm();
            if (d < best && nrm[size_t(k)].dot(qn) > kLeastNormalAgreement) {
              best = d, mirror[e] = k;
            }
          }
        }
      }
    }
  }
  return mirror;
}

uint32_t MirrorFillGap(uint32_t atlas_size) {
  return std::max(1u, uint32_t(std::lround(atlas_size * 6.0 / 512)));
}

std::vector<std::pair<uint32_t, uint32_t>> MirrorFillTargets(const TexelMap& map,
                                                             const std::vector<int32_t>& mirror,
                                                             const std::vector<uint8_t>& held,
                                                             const std::vector<uint8_t>& seen,
                                                             uint32_t gap) {
  const uint32_t size = map.size;
  // Steps from the nearest held texel, spread over the map's texels up to
  // `gap`; kFar: unheld and further (or cut off from every held texel).
  constexpr int32_t kOutside = -2, kFar = -1;
  std::vector<int32_t> steps(size_t(size) * size, kOutside);
  std::vector<uint32_t> queue;
  for (uint32_t texel : map.texel) {
    steps[texel] = held[texel] ? 0 : kFar;
    if (held[texel]) queue.push_back(texel);
  }
  for (size_t q = 0; q < queue.size(); ++q) {
    const uint32_t at = queue[q];
    if (uint32_t(steps[at]) >= gap) continue;
    const uint32_t x = at % size, y = at / size;
    const uint32_t next[4] = {x > 0 ? at - 1 : at, x + 1 < size ? at + 1 : at,
                              y > 0 ? at - size : at, y + 1 < size ? at + size : at};
    for (uint32_t nb : next) {
      if (steps[nb] == kFar) steps[nb] = steps[at] + 1, queue.push_back(nb);
    }
  }
  std::vector<std::pair<uint32_t, uint32_t>> targets;
  for (size_t e = 0; e < map.texel.size(); ++e) {
    if (steps[map.texel[e]] != kFar || mirror[e] < 0) continue;
    if (!seen[map.texel[size_t(mirror[e])]]) continue;
    targets.emplace_back(uint32_t(e), uint32_t(mirror[e]));
  }
  return targets;
}

}  // namespace fvv
