#include "encoder/encode/occluders.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

#include "encoder/capture/calibration.h"
#include "encoder/encode/mask_dilation.h"
#include "encoder/shape/depth_map.h"

namespace fvv {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;
using Eigen::Vector3f;

constexpr float kNothing = std::numeric_limits<float>::infinity();

// One camera at working size: its calibration scaled, its silhouette reduced
// (a reduced pixel is foreground if any of its pixels is), grown by a pixel
// for the voxels' footprint, and the foreground the actor's model does not
// explain.
struct View {
  Camera camera;
  int factor = 1, w = 0, h = 0;
  std::vector<uint8_t> foreground;          // grown by a pixel
  std::vector<uint8_t> unexplained;         // grown by a pixel
  std::vector<uint8_t> unexplained_pixels;  // not grown
  uint64_t unexplained_count = 0, covered_count = 0;

  // The reduced pixel `world` falls in, or false outside the image.
  bool Pixel(const Vector3d& world, size_t* index, double* z) const {
    Vector2d q;
    if (!ProjectPoint(camera, world, &q, z)) return false;
    if (!(q.x() > -0.5 && q.y() > -0.5 && q.x() < w - 0.5 && q.y() < h - 0.5)) return false;
    const int x = std::min(w - 1, int(std::lround(q.x()))),
              y = std::min(h - 1, int(std::lround(q.y())));
    *index = size_t(y) * w + x;
    return true;
  }
};

View MakeView(const Camera& full, const Image& silhouette,
              const std::vector<std::array<uint32_t, 3>>& triangles,
              const std::vector<Vector3f>& positions, const Vector3d& actor_centre,
              const OccluderOptions& o) {
  View v;
  v.factor = ReductionFactor(full, o.max_side);
  const int f = v.factor;
  v.camera = ReducedCamera(full, f);
  v.w = int(v.camera.width);
  v.h = int(v.camera.height);
  std::vector<uint8_t> any(size_t(v.w) * v.h, 0);
  const int ch = std::max(1, int(silhouette.channels));
  for (int y = 0; y < v.h; ++y) {
    for (int x = 0; x < v.w; ++x) {
      uint8_t set = 0;
      for (int dy = 0; dy < f && !set; ++dy) {
        const uint8_t* row =
            &silhouette.pixels[(size_t(y * f + dy) * silhouette.width + size_t(x) * f) * ch];
        for (int dx = 0; dx < f && !set; ++dx) set = row[dx * ch] != 0;
      }
      any[size_t(y) * v.w + x] = set;
    }
  }
  // The actor's model as this camera sees it, grown by the fit's error at
  // his depth.
  const DepthMap model = RenderDepthMap(triangles, positions, v.camera);
  std::vector<uint8_t> covered(any.size());
  for (size_t i = 0; i < covered.size(); ++i) {
    covered[i] = std::isfinite(model.depth[i]);
    v.covered_count += covered[i];
  }
  Vector2d q;
  double z = 0;
  int margin = 1;
  if (ProjectPoint(v.camera, actor_centre, &q, &z) && z > 0) {
    margin = std::max(1, int(std::ceil(o.explained_margin * v.camera.fx / z)));
  }
  const std::vector<uint8_t> explained = DilateMask(covered.data(), v.w, v.h, margin);
  std::vector<uint8_t> unexplained(any.size());
  for (size_t i = 0; i < any.size(); ++i) {
    unexplained[i] = any[i] && !explained[i];
    v.unexplained_count += unexplained[i];
  }
  v.foreground = DilateMask(any.data(), v.w, v.h, 1);
  v.unexplained = DilateMask(unexplained.data(), v.w, v.h, 1);
  v.unexplained_pixels = std::move(unexplained);
  return v;
}

}  // namespace

bool OccluderDepth::Hides(int x, int y, double z, double clearance) const {
  if (factor == 0) return false;
  const int rx = x / factor, ry = y / factor;
  if (rx < 0 || ry < 0 || rx >= width || ry >= height) return false;
  return depth[size_t(ry) * width + rx] < z - clearance;
}

std::vector<OccluderDepth> FindOccluders(const std::vector<Camera>& cameras,
                                         const std::vector<Image>& silhouettes,
                                         const std::vector<std::array<uint32_t, 3>>& triangles,
                                         const std::vector<Vector3f>& positions,
                                         const OccluderOptions& o, OccluderReport* report,
                                         const ParallelRunner& runner) {
  std::vector<OccluderDepth> out(cameras.size());
  if (report) *report = OccluderReport();
  if (!o.enabled || positions.empty() || silhouettes.size() != cameras.size() ||
      cameras.size() < 2) {
    return out;
  }
  for (size_t c = 0; c < cameras.size(); ++c) {
    if (silhouettes[c].width != cameras[c].width || silhouettes[c].height != cameras[c].height) {
      return out;
    }
  }
  Vector3d lo = positions[0].cast<double>(), hi = lo;
  for (const Vector3f& p : positions) {
    lo = lo.cwiseMin(p.cast<double>());
    hi = hi.cwiseMax(p.cast<double>());
  }
  const Vector3d actor_centre = (lo + hi) / 2;
  std::vector<View> views(cameras.size());
  runner(uint32_t(cameras.size()), [&](uint32_t c) {
    views[c] = MakeView(cameras[c], silhouettes[c], triangles, positions, actor_centre, o);
  });
  // Each camera's unexplained foreground that the hull does not account for,
  // as a share of what the model covers. Only voxels another camera also
  // finds unexplained account for it: where one camera's mask alone holds
  // someone, the voxels its foreground leaves near the actor (inside the
  // other cameras' masks of him) are no confirmation.
  std::vector<std::vector<uint8_t>> confirmed(views.size());
  const auto share = [&]() {
    if (!report) return;
    report->unexplained_share.clear();
    for (size_t c = 0; c < views.size(); ++c) {
      const View& v = views[c];
      uint64_t left = v.unexplained_count;
      if (!confirmed[c].empty()) {
        left = 0;
        for (size_t i = 0; i < v.unexplained_pixels.size(); ++i) {
          left += v.unexplained_pixels[i] && !confirmed[c][i];
        }
      }
      report->unexplained_share.push_back(double(left) /
                                          double(std::max<uint64_t>(1, v.covered_count)));
    }
  };
  uint64_t unexplained = 0;
  for (const View& v : views) unexplained += v.unexplained_count;
  share();
  if (unexplained == 0) return out;

  // The grid around the actor; voxels grow until it fits the cap.
  lo.array() -= o.reach;
  hi.array() += o.reach;
  double size = o.voxel_size;
  std::array<int, 3> dims{};
  for (;;) {
    for (int k = 0; k < 3; ++k) dims[k] = std::max(1, int(std::ceil((hi[k] - lo[k]) / size)));
    if (uint64_t(dims[0]) * dims[1] * dims[2] <= o.max_voxels) break;
    size *= 1.25;
  }
  // A voxel is something else's when every camera that sees it finds it in
  // its silhouette (at least two see it) and one finds it where the actor's
  // model does not reach.
  struct Voxel {
    Vector3d p;
    int lone;  // the one camera that finds it unexplained, or -1 (two or more)
  };
  std::vector<std::vector<Voxel>> slab_voxels(static_cast<size_t>(dims[2]));
  runner(uint32_t(dims[2]), [&](uint32_t zi) {
    for (int yi = 0; yi < dims[1]; ++yi) {
      for (int xi = 0; xi < dims[0]; ++xi) {
        const Vector3d p = lo + size * Vector3d(xi + 0.5, yi + 0.5, zi + 0.5);
        int seen = 0, elsewhere = 0, lone = -1;
        bool kept = true;
        for (const View& v : views) {
          size_t i = 0;
          double z = 0;
          if (!v.Pixel(p, &i, &z)) continue;
          ++seen;
          if (!v.foreground[i]) {
            kept = false;
            break;
          }
          if (v.unexplained[i]) ++elsewhere, lone = int(&v - views.data());
        }
        if (kept && elsewhere > 0 && seen >= 2) {
          slab_voxels[zi].push_back({p, elsewhere == 1 ? lone : -1});
        }
      }
    }
  });
  std::vector<Voxel> voxels;
  for (const auto& s : slab_voxels) voxels.insert(voxels.end(), s.begin(), s.end());
  if (report) report->voxels = voxels.size();
  if (voxels.empty()) return out;

  // Each camera's depth of them: every voxel drawn as a disc its size.
  runner(uint32_t(cameras.size()), [&](uint32_t c) {
    const View& v = views[c];
    OccluderDepth& d = out[c];
    d.factor = v.factor;
    d.width = v.w;
    d.height = v.h;
    d.depth.assign(size_t(v.w) * v.h, kNothing);
    confirmed[c].assign(size_t(v.w) * v.h, 0);
    for (const Voxel& voxel : voxels) {
      const Vector3d& p = voxel.p;
      const bool confirms = voxel.lone != int(c);
      Vector2d q;
      double z = 0;
      if (!ProjectPoint(v.camera, p, &q, &z)) continue;
      const double r = 0.5 * size * v.camera.fx / z;
      if (!(q.x() >= -r && q.y() >= -r && q.x() <= v.w + r && q.y() <= v.h + r)) continue;
      const int x0 = std::max(0, int(std::floor(q.x() - r))),
                x1 = std::min(v.w - 1, int(q.x() + r));
      const int y0 = std::max(0, int(std::floor(q.y() - r))),
                y1 = std::min(v.h - 1, int(q.y() + r));
      for (int y = y0; y <= y1; ++y) {
        for (int x = x0; x <= x1; ++x) {
          float& here = d.depth[size_t(y) * v.w + x];
          here = std::min(here, float(z - 0.5 * size));
          confirmed[c][size_t(y) * v.w + x] |= confirms;
        }
      }
    }
  });
  share();
  return out;
}

}  // namespace fvv
