#include "encoder/shape/visual_hull.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <unordered_map>

#include "encoder/capture/calibration.h"

namespace fvv {
namespace {

// Per camera: the distance (pixels, chamfer 3-4 / 3) from each pixel to the
// nearest silhouette pixel, so one lookup says whether a voxel's footprint
// reaches the silhouette.
std::vector<float> DistanceToSilhouette(const Image& s) {
  const int w = static_cast<int>(s.width), h = static_cast<int>(s.height);
  const float inf = 1e9f;
  std::vector<float> d(size_t(w) * h);
  for (size_t i = 0; i < d.size(); ++i) d[i] = s.pixels[i * s.channels] ? 0.0f : inf;
  const auto relax = [&](int x, int y, int dx, int dy, float cost) {
    const int nx = x + dx, ny = y + dy;
    if (nx < 0 || ny < 0 || nx >= w || ny >= h) return;
    float& v = d[size_t(y) * w + x];
    v = std::min(v, d[size_t(ny) * w + nx] + cost);
  };
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      relax(x, y, -1, 0, 3), relax(x, y, 0, -1, 3), relax(x, y, -1, -1, 4), relax(x, y, 1, -1, 4);
    }
  }
  for (int y = h - 1; y >= 0; --y) {
    for (int x = w - 1; x >= 0; --x) {
      relax(x, y, 1, 0, 3), relax(x, y, 0, 1, 3), relax(x, y, 1, 1, 4), relax(x, y, -1, 1, 4);
    }
  }
  for (float& v : d) v /= 3.0f;
  return d;
}

struct View {
  const Camera* camera;
  std::vector<float> distance;
  double focal;  // pixels, for projected radii
};

// Carves the grid: a voxel stays when every camera that sees it has the
// silhouette within its projected radius, and at least min_views see it.
void Carve(const std::vector<View>& views, const VisualHullOptions& o, const ParallelRunner& runner,
           VisualHull* g) {
  const double radius = g->voxel_size * std::sqrt(3.0) / 2;
  g->occupied.assign(size_t(g->dims[0]) * g->dims[1] * g->dims[2], 0);
  runner(static_cast<uint32_t>(g->dims[2]), [&](uint32_t z) {
    for (int y = 0; y < g->dims[1]; ++y) {
      for (int x = 0; x < g->dims[0]; ++x) {
        const Eigen::Vector3d c = g->Centre(x, y, static_cast<int>(z));
        int seen = 0;
        bool keep = true;
        for (const View& v : views) {
          Eigen::Vector2d px;
          double depth = 0;
          if (!ProjectPoint(*v.camera, c, &px, &depth) || depth <= radius) continue;
          const long ix = std::lround(px.x()), iy = std::lround(px.y());
          const long w = v.camera->width, h = v.camera->height;
          if (ix < 0 || iy < 0 || ix >= w || iy >= h) continue;  // this camera cannot tell
          ++seen;
          const double reach = radius * v.focal / depth + o.margin_px + 0.71;
          if (v.distance[size_t(iy) * w + ix] > reach) {
            keep = false;
            break;
          }
        }
        g->occupied[g->Index(x, y, static_cast<int>(z))] = keep && seen >= o.min_views;
      }
    }
  });
}

Status MakeGrid(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double size,
                uint64_t max_voxels, VisualHull* g) {
  g->voxel_size = size;
  g->origin = lo;
  uint64_t total = 1;
  for (int a = 0; a < 3; ++a) {
    g->dims[a] = std::max(1, static_cast<int>(std::ceil((hi[a] - lo[a]) / size)));
    total *= uint64_t(g->dims[a]);
  }
  if (total > max_voxels) {
    return LimitExceeded("visual hull: a grid of " + std::to_string(g->dims[0]) + "x" +
                         std::to_string(g->dims[1]) + "x" + std::to_string(g->dims[2]) +
                         " voxels of " + std::to_string(size) + " m is over the limit of " +
                         std::to_string(max_voxels));
  }
  return Status::Ok();
}

}  // namespace

bool VisualHull::At(int x, int y, int z) const {
  if (x < 0 || y < 0 || z < 0 || x >= dims[0] || y >= dims[1] || z >= dims[2]) return false;
  return occupied[Index(x, y, z)] != 0;
}

Eigen::Vector3d VisualHull::Centre(int x, int y, int z) const {
  return origin + voxel_size * Eigen::Vector3d(x + 0.5, y + 0.5, z + 0.5);
}

bool VisualHull::Contains(const Eigen::Vector3d& p) const {
  const Eigen::Vector3d q = (p - origin) / voxel_size;
  return At(static_cast<int>(std::floor(q.x())), static_cast<int>(std::floor(q.y())),
            static_cast<int>(std::floor(q.z())));
}

size_t VisualHull::OccupiedCount() const {
  return static_cast<size_t>(std::count(occupied.begin(), occupied.end(), 1));
}

double VisualHull::Volume() const { return OccupiedCount() * voxel_size * voxel_size * voxel_size; }

std::vector<Eigen::Vector3d> VisualHull::SurfaceVoxels() const {
  std::vector<Eigen::Vector3d> out;
  for (int z = 0; z < dims[2]; ++z) {
    for (int y = 0; y < dims[1]; ++y) {
      for (int x = 0; x < dims[0]; ++x) {
        if (!At(x, y, z)) continue;
        if (!At(x - 1, y, z) || !At(x + 1, y, z) || !At(x, y - 1, z) || !At(x, y + 1, z) ||
            !At(x, y, z - 1) || !At(x, y, z + 1)) {
          out.push_back(Centre(x, y, z));
        }
      }
    }
  }
  return out;
}

StatusOr<VisualHull> CarveVisualHull(const std::vector<Camera>& cameras,
                                     const std::vector<Image>& silhouettes,
                                     const VisualHullOptions& o, const ParallelRunner& runner) {
  if (cameras.size() < 2 || cameras.size() != silhouettes.size()) {
    return InvalidArgument("visual hull: needs two or more cameras, one silhouette each (" +
                           std::to_string(cameras.size()) + " cameras, " +
                           std::to_string(silhouettes.size()) + " silhouettes)");
  }
  if (!(o.voxel_size > 0) || !(o.coarse_size >= o.voxel_size) || !(o.margin_px >= 0) ||
      o.min_views < 1) {
    return InvalidArgument("visual hull: voxel size > 0, coarse size >= voxel size, margin >= 0");
  }
  std::vector<View> views(cameras.size());
  Eigen::Vector3d lo = CameraCentre(cameras[0]), hi = lo;
  for (size_t k = 0; k < cameras.size(); ++k) {
    const Image& s = silhouettes[k];
    if (s.width != cameras[k].width || s.height != cameras[k].height) {
      return InvalidArgument(
          "visual hull: silhouette " + std::to_string(k) + " is " + std::to_string(s.width) + "x" +
          std::to_string(s.height) + ", camera \"" + cameras[k].name + "\" is " +
          std::to_string(cameras[k].width) + "x" + std::to_string(cameras[k].height));
    }
    views[k].camera = &cameras[k];
    views[k].distance = DistanceToSilhouette(s);
    views[k].focal = std::max(cameras[k].fx, cameras[k].fy);
    lo = lo.cwiseMin(CameraCentre(cameras[k]));
    hi = hi.cwiseMax(CameraCentre(cameras[k]));
  }
  // The studio: the cameras' bounding box grown by half its largest side, so
  // that an actor below or above a ring of cameras is inside it.
  const double grow = 0.5 * (hi - lo).maxCoeff();
  lo.array() -= grow;
  hi.array() += grow;
  VisualHull coarse;
  FVV_RETURN_IF_ERROR(MakeGrid(lo, hi, o.coarse_size, o.max_voxels, &coarse));
  Carve(views, o, runner, &coarse);
  Eigen::Vector3d found_lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::max());
  Eigen::Vector3d found_hi = -found_lo;
  for (int z = 0; z < coarse.dims[2]; ++z) {
    for (int y = 0; y < coarse.dims[1]; ++y) {
      for (int x = 0; x < coarse.dims[0]; ++x) {
        if (!coarse.At(x, y, z)) continue;
        const Eigen::Vector3d c = coarse.Centre(x, y, z);
        found_lo = found_lo.cwiseMin(c);
        found_hi = found_hi.cwiseMax(c);
      }
    }
  }
  if (coarse.OccupiedCount() == 0) {
    return InvalidArgument(
        "visual hull: the silhouettes have no volume in common (empty "
        "silhouettes, or a calibration that does not match them)");
  }
  VisualHull fine;
  FVV_RETURN_IF_ERROR(MakeGrid(found_lo.array() - o.coarse_size, found_hi.array() + o.coarse_size,
                               o.voxel_size, o.max_voxels, &fine));
  Carve(views, o, runner, &fine);
  return fine;
}

void VisualHull::SurfaceMesh(std::vector<Eigen::Vector3f>* positions,
                             std::vector<std::array<uint32_t, 3>>* triangles) const {
  positions->clear();
  triangles->clear();
  std::unordered_map<uint64_t, uint32_t> corner_index;
  const auto corner = [&](int x, int y, int z) {
    const uint64_t key =
        (uint64_t(uint32_t(x)) << 42) | (uint64_t(uint32_t(y)) << 21) | uint64_t(uint32_t(z));
    const auto it = corner_index.emplace(key, uint32_t(positions->size()));
    if (it.second) {
      positions->push_back((origin + voxel_size * Eigen::Vector3d(x, y, z)).cast<float>());
    }
    return it.first->second;
  };
  // Per axis and side: the neighbour offset and the face's corners,
  // counter-clockwise seen from outside.
  struct Face {
    int dx, dy, dz;
    int c[4][3];
  };
  static const Face kFaces[6] = {
      {-1, 0, 0, {{0, 0, 0}, {0, 0, 1}, {0, 1, 1}, {0, 1, 0}}},
      {1, 0, 0, {{1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {1, 0, 1}}},
      {0, -1, 0, {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}}},
      {0, 1, 0, {{0, 1, 0}, {0, 1, 1}, {1, 1, 1}, {1, 1, 0}}},
      {0, 0, -1, {{0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}}},
      {0, 0, 1, {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}}},
  };
  for (int z = 0; z < dims[2]; ++z) {
    for (int y = 0; y < dims[1]; ++y) {
      for (int x = 0; x < dims[0]; ++x) {
        if (!occupied[Index(x, y, z)]) continue;
        for (const Face& f : kFaces) {
          if (At(x + f.dx, y + f.dy, z + f.dz)) continue;
          uint32_t q[4];
          for (int k = 0; k < 4; ++k) q[k] = corner(x + f.c[k][0], y + f.c[k][1], z + f.c[k][2]);
          triangles->push_back({q[0], q[1], q[2]});
          triangles->push_back({q[0], q[2], q[3]});
        }
      }
    }
  }
}

Status WritePointCloudPly(const std::string& path, const std::vector<Eigen::Vector3d>& points) {
  std::string text = "ply\nformat ascii 1.0\nelement vertex " + std::to_string(points.size()) +
                     "\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
  char line[96];
  for (const Eigen::Vector3d& p : points) {
    const int n = std::snprintf(line, sizeof(line), "%.4f %.4f %.4f\n", p.x(), p.y(), p.z());
    text.append(line, static_cast<size_t>(n));
  }
  return WriteFileAtomic(path, reinterpret_cast<const uint8_t*>(text.data()), text.size());
}

}  // namespace fvv
