// Nearest points on a surface: a triangle mesh, or a point set (the visual
// hull's surface voxels), bucketed into a uniform grid so a query looks only
// at the cells around the point, ring by ring, until no nearer triangle can
// remain. What shape refinement's silhouette term and the surface-distance
// measurements (tests, benchmark) query.
#ifndef FVV_ENCODER_SHAPE_SURFACE_INDEX_H_
#define FVV_ENCODER_SHAPE_SURFACE_INDEX_H_

#include <Eigen/Core>
#include <array>
#include <vector>

namespace fvv {

class SurfaceIndex {
 public:
  // A triangle mesh (world positions; degenerate triangles count as their
  // points and edges).
  SurfaceIndex(const std::vector<Eigen::Vector3f>& positions,
               const std::vector<std::array<uint32_t, 3>>& triangles, double cell = 0.04);
  // A point set.
  static SurfaceIndex Points(const std::vector<Eigen::Vector3d>& points, double cell = 0.04);

  // Distance from `p` to the surface, and the nearest point when `closest` is
  // not null; +infinity for an empty surface.
  double Nearest(const Eigen::Vector3d& p, Eigen::Vector3d* closest = nullptr) const;

 private:
  SurfaceIndex() = default;
  void Build(double cell);
  std::vector<Eigen::Vector3d> points_;
  std::vector<std::array<uint32_t, 3>> triangles_;
  Eigen::Vector3d origin_{0, 0, 0};
  double cell_ = 0.04;
  std::array<int, 3> dims_{0, 0, 0};
  std::vector<uint32_t> start_;  // per cell: its first entry in `entries_` (CSR)
  std::vector<uint32_t> entries_;
};

// Distances from points to a surface, summarised.
struct DistanceSummary {
  double mean = 0, p95 = 0, max = 0;
  size_t count = 0;
};
DistanceSummary SummariseDistances(const std::vector<Eigen::Vector3d>& points,
                                   const SurfaceIndex& surface);

// Closest point of triangle abc to p.
Eigen::Vector3d ClosestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                       const Eigen::Vector3d& b, const Eigen::Vector3d& c);

}  // namespace fvv

#endif  // FVV_ENCODER_SHAPE_SURFACE_INDEX_H_
