#include "encoder/shape/surface_tracking.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "encoder/body/mesh_ops.h"
#include "encoder/capture/calibration.h"
#include "encoder/shape/projective_texturing.h"
#include "encoder/track/silhouette_raster.h"

namespace fvv {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

// One camera at working size: its calibration scaled, the silhouette
// reduced by majority, and per pixel the signed distance (pixels) to its
// outline.
struct View {
  Camera camera;
  Vector3d centre;
  int w = 0, h = 0;
  std::vector<uint8_t> inside;
  std::vector<float> distance;
  std::vector<uint8_t> model;  // the posed model's own silhouette, redrawn each step

  bool In(int x, int y) const { return x >= 0 && y >= 0 && x < w && y < h; }
  // The signed distance at `q`, bilinear between pixel centres; outside the
  // image, far outside.
  double Signed(const Vector2d& q) const {
    const int x0 = int(std::floor(q.x())), y0 = int(std::floor(q.y()));
    if (x0 < 0 || y0 < 0 || x0 + 1 >= w || y0 + 1 >= h) return 64.0;
    const double fx = q.x() - x0, fy = q.y() - y0;
    const float* r0 = &distance[size_t(y0) * w + x0];
    const float* r1 = r0 + w;
    return (1 - fy) * ((1 - fx) * r0[0] + fx * r0[1]) + fy * ((1 - fx) * r1[0] + fx * r1[1]);
  }
  bool Model(const Vector2d& q) const {
    const int x = int(std::lround(q.x())), y = int(std::lround(q.y()));
    return In(x, y) && model[size_t(y) * w + x];
  }
};

View MakeView(const Camera& full, const Image& sil, int max_side) {
  View v;
  const int factor = ReductionFactor(full, max_side);
  v.camera = ReducedCamera(full, factor);
  v.w = int(v.camera.width);
  v.h = int(v.camera.height);
  v.centre = CameraCentre(full);
  v.inside.assign(size_t(v.w) * v.h, 0);
  const int ch = sil.channels;
  for (int y = 0; y < v.h; ++y) {
    for (int x = 0; x < v.w; ++x) {
      int count = 0;
      for (int dy = 0; dy < factor; ++dy) {
        const uint8_t* row = &sil.pixels[(size_t(y * factor + dy) * sil.width + x * factor) * ch];
        for (int dx = 0; dx < factor; ++dx) count += row[dx * ch] != 0;
      }
      v.inside[size_t(y) * v.w + x] = 2 * count >= factor * factor;
    }
  }
  // Signed distance to the silhouette's outline (pixels; negative inside):
  // two-pass chamfer distances to the nearest pixel of the other kind, less
  // half a pixel, so that the outline runs between pixel centres and the
  // field can be read between them (Signed), without the half-pixel bias of
  // asking which pixel a vertex falls in.
  constexpr float kBig = 1e9f;
  const auto chamfer = [&](bool to_inside) {
    std::vector<float> d(v.inside.size(), kBig);
    for (size_t i = 0; i < v.inside.size(); ++i) {
      if (bool(v.inside[i]) == to_inside) d[i] = 0;
    }
    const auto relax = [&](int x, int y, int dx, int dy, float cost) {
      if (!v.In(x + dx, y + dy)) return;
      float& here = d[size_t(y) * v.w + x];
      here = std::min(here, d[size_t(y + dy) * v.w + x + dx] + cost);
    };
    for (int y = 0; y < v.h; ++y) {
      for (int x = 0; x < v.w; ++x) {
        relax(x, y, -1, 0, 1.0f), relax(x, y, 0, -1, 1.0f);
        relax(x, y, -1, -1, 1.4142f), relax(x, y, 1, -1, 1.4142f);
      }
    }
    for (int y = v.h - 1; y >= 0; --y) {
      for (int x = v.w - 1; x >= 0; --x) {
        relax(x, y, 1, 0, 1.0f), relax(x, y, 0, 1, 1.0f);
        relax(x, y, 1, 1, 1.4142f), relax(x, y, -1, 1, 1.4142f);
      }
    }
    return d;
  };
  const std::vector<float> to_inside = chamfer(true), to_outside = chamfer(false);
  v.distance.resize(v.inside.size());
  for (size_t i = 0; i < v.inside.size(); ++i) {
    v.distance[i] = v.inside[i] ? -(std::min(to_outside[i], 64.0f) - 0.5f)
                                : std::min(to_inside[i], 64.0f) - 0.5f;
  }
  v.model.assign(v.inside.size(), 0);
  return v;
}

// Pixels a move of one metre along `a` (the vertex's posed normal direction)
// shifts the image of `p` by, and that shift's unit image direction; false
// when the shift is too small to measure (the normal along the ray).
bool ImageShift(const View& v, const Vector3d& p, const Vector3d& a, Vector2d* q, double* px_per_m,
                Vector2d* dir, double* depth) {
  if (!ProjectPoint(v.camera, p, q, depth)) return false;
  Vector2d q2;
  const double eps = 0.005;
  if (!ProjectPoint(v.camera, p + eps * a, &q2)) return false;
  const Vector2d d = (q2 - *q) / eps;
  *px_per_m = d.norm();
  if (*px_per_m < 1e-6) return false;
  *dir = d / *px_per_m;
  return true;
}

}  // namespace

SurfaceTracker::SurfaceTracker(const Mesh& mesh, const SurfaceTrackingOptions& options)
    : mesh_(mesh), o_(options) {
  welded_ = WeldVertices(MeshPositions(mesh));
  for (uint32_t v = 0; v < welded_.size(); ++v) {
    if (welded_[v] == v) canonical_.push_back(v);
  }
  ring_ = VertexNeighbours(mesh.triangles, welded_);
  for (const auto& t : mesh.triangles) tris_.insert(tris_.end(), t.begin(), t.end());
  previous_.assign(mesh.positions.size(), 0.0f);
}

bool RigSuitsStereo(const std::vector<Camera>& cameras, const Vector3d& actor,
                    const SurfaceTrackingOptions& o) {
  std::vector<Vector3d> towards;
  for (const Camera& c : cameras) {
    const Vector3d centre = CameraCentre(c);
    const double distance = (centre - actor).norm();
    const Camera working = ReducedCamera(c, ReductionFactor(c, o.max_side));
    if (!(distance > 0) || distance / std::min(working.fx, working.fy) > o.stereo_max_pixel) {
      return false;
    }
    towards.push_back((centre - actor) / distance);
  }
  for (size_t i = 0; i < towards.size(); ++i) {
    int near = 0;
    for (size_t j = 0; j < towards.size(); ++j) {
      if (j == i) continue;
      near +=
          std::acos(std::clamp(towards[i].dot(towards[j]), -1.0, 1.0)) < o.stereo_match.max_angle;
    }
    if (near < o.stereo_match.min_neighbours) return false;
  }
  return !towards.empty();
}

size_t SurfaceTracker::Match(const std::vector<Vector3d>& p, const StereoViews& views,
                             std::vector<StereoTarget>* out, const ParallelRunner& runner) const {
  std::vector<Eigen::Vector3f> pf(p.size());
  for (size_t v = 0; v < p.size(); ++v) pf[v] = p[v].cast<float>();
  const std::vector<Eigen::Vector3f> normals = VertexNormals(mesh_.triangles, pf, welded_);
  // Seen by a camera that faces the surface (depth test at working size).
  ProjectiveOptions po;
  po.shift_m = 0;
  po.depth_tolerance = 0.01;
  po.min_facing = 0.2;
  const std::vector<std::vector<uint8_t>> vis =
      VertexVisibility(mesh_.triangles, pf, normals, views.cameras, po, runner);
  constexpr uint32_t kChunks = 64;
  std::vector<size_t> counts(kChunks, 0);
  runner(kChunks, [&](uint32_t chunk) {
    std::vector<uint8_t> seen(views.cameras.size());
    for (size_t i = chunk; i < canonical_.size(); i += kChunks) {
      const uint32_t v = canonical_[i];
      for (size_t c = 0; c < seen.size(); ++c) seen[c] = vis[c][v];
      const Vector3d normal = normals[v].cast<double>();
      (*out)[v] =
          MatchAlongKeyRay(views, seen, p[v], normal, FitSurface(p[v], normal, ring_[v], pf),
                           o_.reach, o_.stereo_match);
      counts[chunk] += (*out)[v].valid;
    }
  });
  size_t total = 0;
  for (size_t c : counts) total += c;
  return total;
}

StatusOr<std::vector<float>> SurfaceTracker::Track(const std::vector<Affine>& skinning,
                                                   const std::vector<Camera>& cameras,
                                                   const std::vector<Image>& silhouettes,
                                                   const std::vector<Image>& images,
                                                   SurfaceTrackingReport* report,
                                                   const ParallelRunner& runner) {
  if (silhouettes.size() != cameras.size()) {
    return InvalidArgument("surface tracking: " + std::to_string(silhouettes.size()) +
                           " silhouettes for " + std::to_string(cameras.size()) + " cameras");
  }
  const size_t n = mesh_.positions.size();
  // The posed surface as a function of the displacement d along the bind
  // normal: p(d) = base + d * along (linear blend skinning is linear).
  std::vector<Vector3d> base(n), along(n);
  runner(64, [&](uint32_t chunk) {
    for (size_t v = chunk; v < n; v += 64) {
      Eigen::Matrix4d m = Eigen::Matrix4d::Zero();
      for (int k = 0; k < kMaxInfluences; ++k) {
        if (mesh_.weights[v][k] == 0 || mesh_.joints[v][k] >= skinning.size()) continue;
        m += (mesh_.weights[v][k] / 65535.0) * skinning[mesh_.joints[v][k]].matrix();
      }
      const Vector3d x(mesh_.positions[v][0], mesh_.positions[v][1], mesh_.positions[v][2]);
      const Vector3d nb(mesh_.normals[v][0], mesh_.normals[v][1], mesh_.normals[v][2]);
      base[v] = m.topLeftCorner<3, 3>() * x + m.topRightCorner<3, 1>();
      along[v] = m.topLeftCorner<3, 3>() * nb;
    }
  });
  std::vector<View> views;
  std::vector<uint32_t> used;
  for (size_t c = 0; c < cameras.size(); ++c) {
    const Image& s = silhouettes[c];
    if (s.pixels.empty()) continue;
    if (s.width != cameras[c].width || s.height != cameras[c].height) {
      return InvalidArgument("surface tracking: camera " + cameras[c].name + "'s silhouette is " +
                             std::to_string(s.width) + "x" + std::to_string(s.height) +
                             ", its calibration " + std::to_string(cameras[c].width) + "x" +
                             std::to_string(cameras[c].height));
    }
    used.push_back(uint32_t(c));
  }
  if (!started_ && (o_.stereo < 0 || o_.temporal < 0)) {
    // The weights by the rig, once: the cameras that see this frame, the
    // actor where the fitted body stands.
    std::vector<Camera> seeing;
    for (uint32_t c : used) seeing.push_back(cameras[c]);
    Vector3d actor = Vector3d::Zero();
    for (const Vector3d& b : base) actor += b / double(n);
    const bool suits = !images.empty() && RigSuitsStereo(seeing, actor, o_);
    if (o_.stereo < 0) o_.stereo = suits ? kStereoRigSurfaceStereo : 0.0;
    if (o_.temporal < 0)
      o_.temporal = suits && o_.stereo > 0 ? kStereoRigSurfaceTemporal : kSurfaceTemporal;
  }
  const bool stereo = o_.stereo > 0 && !images.empty();
  if (stereo && images.size() != cameras.size()) {
    return InvalidArgument("surface tracking: " + std::to_string(images.size()) + " images for " +
                           std::to_string(cameras.size()) + " cameras");
  }
  if (stereo) {
    for (uint32_t c : used) {
      const Image& im = images[c];
      if (im.width != cameras[c].width || im.height != cameras[c].height || im.channels < 3) {
        return InvalidArgument("surface tracking: camera " + cameras[c].name +
                               "'s image is not colour of its calibrated size");
      }
    }
  }
  views.resize(used.size());
  StereoViews stereo_views;
  if (stereo) stereo_views.grey.resize(used.size());
  runner(uint32_t(used.size()), [&](uint32_t k) {
    views[k] = MakeView(cameras[used[k]], silhouettes[used[k]], o_.max_side);
    if (stereo) {
      stereo_views.grey[k] = Grey(images[used[k]], ReductionFactor(cameras[used[k]], o_.max_side));
    }
  });
  if (stereo) {
    for (const View& view : views) {
      stereo_views.cameras.push_back(view.camera);
      stereo_views.centres.push_back(view.centre);
    }
  }
  std::vector<StereoTarget> matches(stereo ? n : 0);
  size_t matched = 0;
  std::vector<float> d = previous_;
  std::vector<double> move(n), weight(n);
  std::vector<uint8_t> outside(n), contour(n);
  // The first frame starts from the fitted body, not from a frame before.
  const int steps = started_ ? o_.steps : 3 * o_.steps;
  const double temporal = started_ ? o_.temporal : 0.0;  // nothing to hold to yet
  started_ = true;
  for (int step = 0; step < steps; ++step) {
    std::vector<Vector3d> p(n);
    for (size_t v = 0; v < n; ++v) p[v] = base[v] + double(d[v]) * along[v];
    if (stereo && step % std::max(1, o_.stereo_every) == 0) {
      matched = Match(p, stereo_views, &matches, runner);
    }
    runner(uint32_t(views.size()), [&](uint32_t k) {
      View& view = views[k];
      std::vector<Eigen::Vector2f> px(n);
      for (size_t v = 0; v < n; ++v) {
        Vector2d q;
        px[v] =
            ProjectPoint(view.camera, p[v], &q) ? q.cast<float>() : Eigen::Vector2f(-1e6f, -1e6f);
      }
      std::fill(view.model.begin(), view.model.end(), 0);
      RasterBox box{0, 0, -1, -1};
      RasteriseSilhouette(tris_, px, view.w, view.h, view.model.data(), &box);
    });
    runner(64, [&](uint32_t chunk) {
      for (size_t i = chunk; i < canonical_.size(); i += 64) {
        const uint32_t v = canonical_[i];
        const Vector3d a = along[v];
        double inward = 0, outward_sum = 0;
        int outward_count = 0;
        bool out = false, rim = false;
        for (const View& view : views) {
          Vector2d q, dir;
          double scale = 0, depth = 0;
          if (!ImageShift(view, p[v], a, &q, &scale, &dir, &depth)) continue;
          const int x = int(std::lround(q.x())), y = int(std::lround(q.y()));
          if (!view.In(x, y)) continue;
          const Vector3d ray = (p[v] - view.centre).normalized();
          const double facing = a.normalized().dot(ray);
          // A vertex facing the camera moves its image little along its
          // normal: its gap is taken as at least 0.3 of a move across the ray.
          const double per_m = std::max(scale, 0.3 * view.camera.fx / depth);
          const double signed_px = view.Signed(q);
          if (signed_px > 0.25 && std::abs(facing) < o_.outside_cosine) {
            out = true;
            inward = std::min(inward, -signed_px / per_m);
            continue;
          }
          if (std::abs(facing) >= o_.contour_cosine) continue;
          // On this camera's contour: nothing of the model just beyond it.
          if (view.Model(q + 3.0 * dir)) continue;
          rim = true;
          // Out along the normal's image direction to where the field
          // crosses zero (between two samples, linearly).
          const double reach_px = o_.reach * scale;
          double t = 0, before = signed_px;
          bool found = before >= 0;
          while (!found && t < reach_px) {
            const double next = view.Signed(q + (t + 0.5) * dir);
            if (next >= 0) {
              t += 0.5 * (-before) / std::max(1e-9, next - before);
              found = true;
            } else {
              t += 0.5, before = next;
            }
          }
          if (!found) continue;    // the outline is out of reach
          if (t < 0.25) continue;  // on it already, within the field's precision
          outward_sum += t / scale;
          ++outward_count;
        }
        outside[v] = out;
        contour[v] = rim;
        if (out) {
          move[v] = inward, weight[v] = 1;
        } else if (outward_count > 0) {
          move[v] = outward_sum / outward_count, weight[v] = 1;
        } else if (stereo && matches[v].valid) {
          // The move along `a` that takes the surface's tangent plane
          // through the matched point.
          move[v] = (matches[v].point - p[v]).dot(a) / a.squaredNorm();
          weight[v] = o_.stereo * matches[v].score;
        } else {
          move[v] = 0, weight[v] = 0;
        }
      }
    });
    // Spread the data terms over the surface.
    for (int pass = 0; pass < o_.spread; ++pass) {
      std::vector<double> next(move), next_w(weight);
      runner(64, [&](uint32_t chunk) {
        for (size_t i = chunk; i < canonical_.size(); i += 64) {
          const uint32_t v = canonical_[i];
          double sum = weight[v] * move[v], w = weight[v];
          for (uint32_t nb : ring_[v]) sum += weight[nb] * move[nb], w += weight[nb];
          next[v] = w > 0 ? sum / w : 0;
          next_w[v] = w / (1.0 + ring_[v].size());
        }
      });
      move.swap(next);
      weight.swap(next_w);
    }
    std::vector<float> next(d);
    runner(64, [&](uint32_t chunk) {
      for (size_t i = chunk; i < canonical_.size(); i += 64) {
        const uint32_t v = canonical_[i];
        double mean = 0;
        for (uint32_t nb : ring_[v]) mean += d[nb];
        mean = ring_[v].empty() ? d[v] : mean / ring_[v].size();
        const double target =
            (weight[v] * (d[v] + move[v]) + o_.smoothness * mean + temporal * previous_[v]) /
            (weight[v] + o_.smoothness + temporal + o_.prior);
        const double value = d[v] + o_.step * (target - d[v]);
        next[v] = float(std::clamp(value, -o_.max_displacement, o_.max_displacement));
      }
    });
    for (size_t v = 0; v < n; ++v) next[v] = next[welded_[v]];
    d.swap(next);
  }
  previous_ = d;
  if (report) {
    size_t out = 0, rim = 0;
    double sum = 0;
    for (uint32_t v : canonical_) out += outside[v], rim += contour[v], sum += std::abs(d[v]);
    const double count = std::max<size_t>(1, canonical_.size());
    report->outside = out / count;
    report->contour = rim / count;
    report->mean_abs = sum / count;
    report->stereo = matched / count;
    report->temporal_weight = o_.temporal;
    report->stereo_weight = o_.stereo;
  }
  return d;
}

}  // namespace fvv
