#include "encoder/shape/shape_refinement.h"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <mutex>
#include <utility>

#include "encoder/body/kinematics.h"
#include "encoder/body/mesh_ops.h"
#include "encoder/capture/calibration.h"
#include "encoder/shape/depth_map.h"
#include "encoder/shape/patch_stereo.h"
#include "encoder/shape/projective_texturing.h"
#include "encoder/shape/surface_index.h"

namespace fvv {
namespace {

using Eigen::Vector3d;
using Eigen::Vector3f;

// A vertex's position in the frame of three of its 1-ring neighbours a, b, c:
// p = a + alpha (b - a) + beta (c - a) + height * sqrt(|n|) * n / |n|, with
// n = (b - a) x (c - a). Rotation invariant, and scaled with the triangle.
struct LocalFrame {
  uint32_t a, b, c;
  double alpha, beta, height;
};

bool FrameCoordinates(const Vector3d& p, const Vector3d& a, const Vector3d& b, const Vector3d& c,
                      double* alpha, double* beta, double* height) {
  const Vector3d e1 = b - a, e2 = c - a, n = e1.cross(e2);
  const double area2 = n.norm();
  if (!(area2 > 1e-12)) return false;
  const Vector3d d = p - a, unit = n / area2;
  *height = d.dot(unit) / std::sqrt(area2);
  const double g11 = e1.dot(e1), g12 = e1.dot(e2), g22 = e2.dot(e2);
  const double det = g11 * g22 - g12 * g12;
  if (!(det > 1e-18)) return false;
  const double r1 = e1.dot(d), r2 = e2.dot(d);
  *alpha = (g22 * r1 - g12 * r2) / det;
  *beta = (g11 * r2 - g12 * r1) / det;
  return true;
}

Vector3d FromFrame(const LocalFrame& f, const std::vector<Vector3f>& p) {
  const Vector3d a = p[f.a].cast<double>(), e1 = p[f.b].cast<double>() - a,
                 e2 = p[f.c].cast<double>() - a;
  const Vector3d n = e1.cross(e2);
  const double area2 = n.norm();
  Vector3d out = a + f.alpha * e1 + f.beta * e2;
  if (area2 > 1e-12) out += f.height * std::sqrt(area2) * n / area2;
  return out;
}

// What the mesh's connectivity gives once: welded vertices, 1-ring
// neighbours and the neighbour triples of the local frames.
struct Topology {
  std::vector<uint32_t> welded;
  std::vector<uint32_t> canonical;  // the canonical vertices
  std::vector<std::vector<uint32_t>> ring;
  std::vector<std::vector<LocalFrame>> frames;  // per canonical vertex
};

// The local-frame coordinates of every vertex in the shape `p` (the posed
// generic model a frame starts from: what regularisation holds to). Triples
// that are degenerate there are dropped.
std::vector<std::vector<LocalFrame>> FramesOf(const Topology& t, const std::vector<Vector3f>& p) {
  std::vector<std::vector<LocalFrame>> out(t.frames.size());
  for (size_t v = 0; v < t.frames.size(); ++v) {
    for (LocalFrame f : t.frames[v]) {
      if (FrameCoordinates(p[v].cast<double>(), p[f.a].cast<double>(), p[f.b].cast<double>(),
                           p[f.c].cast<double>(), &f.alpha, &f.beta, &f.height)) {
        out[v].push_back(f);
      }
    }
  }
  return out;
}

Topology MakeTopology(const Mesh& mesh) {
  Topology t;
  t.welded = WeldVertices(MeshPositions(mesh));
  for (uint32_t v = 0; v < t.welded.size(); ++v) {
    if (t.welded[v] == v) t.canonical.push_back(v);
  }
  t.ring = VertexNeighbours(mesh.triangles, t.welded);
  // Welded triangles and, per directed edge, the vertex opposite it.
  std::map<std::pair<uint32_t, uint32_t>, std::vector<uint32_t>> opposite;
  std::vector<std::array<uint32_t, 3>> tris;
  for (const auto& tri : mesh.triangles) {
    const std::array<uint32_t, 3> w = {t.welded[tri[0]], t.welded[tri[1]], t.welded[tri[2]]};
    if (w[0] == w[1] || w[1] == w[2] || w[0] == w[2]) continue;
    tris.push_back(w);
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = w[k], b = w[(k + 1) % 3];
      opposite[{std::min(a, b), std::max(a, b)}].push_back(w[(k + 2) % 3]);
    }
  }
  t.frames.resize(t.welded.size());
  for (const auto& w : tris) {
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = w[k], a = w[(k + 1) % 3], b = w[(k + 2) % 3];
      // The triangle across edge (v, a) from this one gives the third point.
      const auto it = opposite.find({std::min(v, a), std::max(v, a)});
      if (it == opposite.end()) continue;
      for (uint32_t c : it->second) {
        if (c == b || c == v || c == a) continue;
        t.frames[v].push_back({a, b, c, 0, 0, 0});
        break;
      }
    }
  }
  return t;
}

// Per vertex, the linear-blend skinning matrix of `dofs`.
std::vector<Eigen::Matrix4d> BlendMatrices(const BodyModel& model,
                                           const std::vector<double>& dofs) {
  const std::vector<Affine> skinning = SkinningMatrices(model.skeleton, dofs);
  std::vector<Eigen::Matrix4d> out(model.mesh.positions.size(), Eigen::Matrix4d::Zero());
  for (size_t v = 0; v < out.size(); ++v) {
    for (int k = 0; k < kMaxInfluences; ++k) {
      const uint16_t j = model.mesh.joints[v][k];
      if (model.mesh.weights[v][k] == 0 || j >= skinning.size()) continue;
      out[v] += (model.mesh.weights[v][k] / 65535.0) * skinning[j].matrix();
    }
  }
  return out;
}

struct Context {
  const BodyModel& model;
  const std::vector<Camera>& cameras;
  const ShapeRefinementOptions& o;
  const Topology& topo;
  std::vector<Vector3d> centres;
  StereoViews stereo;
  const std::vector<Image>* silhouettes = nullptr;
  std::vector<DepthMap> model_depth;  // per camera, of the current shape (per level)
};

bool InSilhouette(const Image& s, const Eigen::Vector2d& q) {
  const long x = std::lround(q.x()), y = std::lround(q.y());
  if (x < 0 || y < 0 || x >= long(s.width) || y >= long(s.height)) return false;
  return s.pixels[size_t(y) * s.width + x] != 0;
}

// Where a vertex on camera `c`'s contour should be: moved along its normal's
// part across the camera's ray (`across`, unit) until it projects onto the
// silhouette's outline, searching up to `range` metres either way. False when
// the outline is not within reach.
bool RimTarget(const Context& ctx, size_t c, const Vector3d& p, const Vector3d& across,
               double range, Vector3d* target) {
  const Image& sil = (*ctx.silhouettes)[c];
  Eigen::Vector2d q0;
  if (!ProjectPoint(ctx.cameras[c], p, &q0)) return false;
  const bool inside = InSilhouette(sil, q0);
  // Half-pixel steps: the pixel footprint at the vertex's depth.
  const double depth = (p - ctx.centres[c]).norm();
  const double step = 0.5 * depth / std::max(ctx.cameras[c].fx, ctx.cameras[c].fy);
  // Only where the model's own outline runs: just beyond the vertex the
  // camera sees nothing of the model. Where another part of the body lies
  // next to it in the image (an arm beside the chest), the silhouette's
  // outline belongs to that part.
  Eigen::Vector2d beyond;
  if (!ProjectPoint(ctx.cameras[c], p + 3 * step * across, &beyond) ||
      std::isfinite(ctx.model_depth[c].At(beyond))) {
    return false;
  }
  const double sign = inside ? 1.0 : -1.0;  // inside: out along `across`; outside: back in
  for (double t = step; t <= range; t += step) {
    Eigen::Vector2d q;
    if (!ProjectPoint(ctx.cameras[c], p + sign * t * across, &q)) return false;
    if (InSilhouette(sil, q) != inside) {
      // The outline lies between this step and the last: take the middle.
      *target = p + sign * (t - 0.5 * step) * across;
      return true;
    }
  }
  return false;
}

// The thin-plate spline (3D: phi(r) = r, plus an affine part) through the
// displacements `values` at `centres`, evaluated at `points`. Fewer than four
// centres, or coplanar ones, cannot fix the affine part: then the mean
// displacement everywhere.
std::vector<Vector3d> ThinPlateDisplacements(const std::vector<Vector3d>& centres,
                                             const std::vector<Vector3d>& values,
                                             const std::vector<Vector3f>& points) {
  const Eigen::Index n = Eigen::Index(centres.size());
  std::vector<Vector3d> out(points.size(), Vector3d::Zero());
  if (n == 0) return out;
  Vector3d mean = Vector3d::Zero();
  for (const Vector3d& v : values) mean += v / double(n);
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(n + 4, n + 4);
  Eigen::MatrixXd b = Eigen::MatrixXd::Zero(n + 4, 3);
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index j = 0; j < n; ++j) a(i, j) = (centres[i] - centres[j]).norm();
    a(i, n) = a(n, i) = 1;
    for (int k = 0; k < 3; ++k) a(i, n + 1 + k) = a(n + 1 + k, i) = centres[i][k];
    b.row(i) = values[i].transpose();
  }
  Eigen::FullPivLU<Eigen::MatrixXd> lu(a);
  if (n < 4 || lu.rank() < n + 4) {
    std::fill(out.begin(), out.end(), mean);
    return out;
  }
  const Eigen::MatrixXd w = lu.solve(b);
  for (size_t v = 0; v < points.size(); ++v) {
    const Vector3d p = points[v].cast<double>();
    Vector3d d = w.row(n).transpose();
    for (int k = 0; k < 3; ++k) d += w.row(n + 1 + k).transpose() * p[k];
    for (Eigen::Index i = 0; i < n; ++i) d += w.row(i).transpose() * (p - centres[i]).norm();
    out[v] = d;
  }
  return out;
}

Status CheckFrame(const BodyModel& model, const std::vector<Camera>& cameras,
                  const RefinementFrame& f) {
  if (f.dofs.size() != model.skeleton.Dofs().size()) {
    return InvalidArgument("shape refinement: " + std::to_string(f.dofs.size()) +
                           " pose values for a skeleton of " +
                           std::to_string(model.skeleton.Dofs().size()));
  }
  if (f.images.size() != cameras.size() || f.silhouettes.size() != cameras.size()) {
    return InvalidArgument("shape refinement: one image and one silhouette per camera");
  }
  for (size_t c = 0; c < cameras.size(); ++c) {
    if (f.images[c].width != cameras[c].width || f.images[c].height != cameras[c].height ||
        f.images[c].channels != 3) {
      return InvalidArgument("shape refinement: camera " + cameras[c].name +
                             "'s image is not RGB of its calibrated size");
    }
  }
  return Status::Ok();
}

Status RefineFrame(const BodyModel& model, const std::vector<Camera>& cameras,
                   const RefinementFrame& frame, const ShapeRefinementOptions& o,
                   const Topology& topo, std::vector<Vector3f>* posed,
                   ShapeRefinementReport* report, const ParallelRunner& runner) {
  FVV_RETURN_IF_ERROR(CheckFrame(model, cameras, frame));
  StatusOr<VisualHull> hull = CarveVisualHull(cameras, frame.silhouettes, o.hull, runner);
  if (!hull.ok()) return hull.status();
  const SurfaceIndex hull_surface = SurfaceIndex::Points(hull->SurfaceVoxels());
  Context ctx{model, cameras, o, topo, {}, {}, &frame.silhouettes, {}};
  for (const Camera& c : cameras) ctx.centres.push_back(CameraCentre(c));
  ctx.stereo.cameras = cameras;
  ctx.stereo.centres = ctx.centres;
  ctx.stereo.grey.resize(cameras.size());
  runner(uint32_t(cameras.size()), [&](uint32_t c) { ctx.stereo.grey[c] = Grey(frame.images[c]); });
  PatchStereoOptions stereo_options;
  stereo_options.patch_radius = o.patch_radius;
  stereo_options.min_ncc = o.min_ncc;
  stereo_options.min_patch_std = o.min_patch_std;
  stereo_options.min_neighbours = 1;

  const std::vector<Eigen::Matrix4d> skin = BlendMatrices(model, frame.dofs);
  std::vector<Vector3f> p(model.mesh.positions.size());
  for (size_t v = 0; v < p.size(); ++v) {
    const Vector3d b(model.mesh.positions[v][0], model.mesh.positions[v][1],
                     model.mesh.positions[v][2]);
    p[v] = (skin[v].topLeftCorner<3, 3>() * b + skin[v].topRightCorner<3, 1>()).cast<float>();
  }
  // Features: the joint errors, interpolated to every vertex, move the whole
  // surface once before the descent (a smooth correction the data terms then
  // refine; as a standing pull it would hold the surface to the start shape).
  if (!frame.features.empty() && o.feature_weight > 0) {
    const std::vector<Vector3d> joints = JointPositions(model.skeleton, frame.dofs);
    std::vector<Vector3d> centres, errors;
    for (const auto& [name, position] : frame.features) {
      for (size_t b = 0; b < model.skeleton.bones.size(); ++b) {
        if (model.skeleton.bones[b].name != name) continue;
        centres.push_back(joints[b]);
        errors.push_back(position - joints[b]);
      }
    }
    const std::vector<Vector3d> d = ThinPlateDisplacements(centres, errors, p);
    for (size_t v = 0; v < p.size(); ++v) p[v] += (o.feature_weight * d[v]).cast<float>();
  }
  // Regularisation holds the posed model's own local shape (skinning bends
  // it away from the bind pose's at the joints; that is not to be undone).
  const std::vector<std::vector<LocalFrame>> local = FramesOf(topo, p);
  const auto& canon = topo.canonical;
  const uint32_t chunks = 64;
  const auto for_canonical = [&](const std::function<void(uint32_t)>& f) {
    runner(chunks, [&](uint32_t chunk) {
      for (size_t i = chunk; i < canon.size(); i += chunks) f(canon[i]);
    });
  };
  if (report && report->levels.size() < o.levels.size()) report->levels.resize(o.levels.size());
  for (size_t level = 0; level < o.levels.size(); ++level) {
    const double range = o.levels[level];
    const std::vector<Vector3f> level_start = p;
    std::vector<Vector3f> normals = VertexNormals(model.mesh.triangles, p, topo.welded);
    // Seen by a camera (depth test), including vertices just past its contour.
    ProjectiveOptions po;
    po.shift_m = 0;
    po.depth_tolerance = 0.01;
    po.min_facing = -o.contour_cosine;
    const std::vector<std::vector<uint8_t>> vis =
        VertexVisibility(model.mesh.triangles, p, normals, cameras, po, runner);
    ctx.model_depth.resize(cameras.size());
    runner(uint32_t(cameras.size()), [&](uint32_t c) {
      ctx.model_depth[c] = RenderDepthMap(model.mesh.triangles, p, cameras[c]);
    });
    std::vector<StereoTarget> stereo(p.size());
    for_canonical([&](uint32_t v) {
      const Vector3d pv = p[v].cast<double>(), nv = normals[v].cast<double>();
      std::vector<uint8_t> seen(cameras.size());
      for (size_t c = 0; c < cameras.size(); ++c) seen[c] = vis[c][v];
      stereo[v] = MatchAlongKeyRay(ctx.stereo, seen, pv, nv, FitSurface(pv, nv, topo.ring[v], p),
                                   range, stereo_options);
    });
    // Per vertex: a camera on whose contour generator it lies (-1: none).
    std::vector<int> contour_camera(p.size(), -1);
    const auto find_contours = [&] {
      for_canonical([&](uint32_t v) {
        contour_camera[v] = -1;
        double best = o.contour_cosine;
        const Vector3d pv = p[v].cast<double>();
        for (size_t c = 0; c < cameras.size(); ++c) {
          if (!vis[c][v]) continue;
          const double f = normals[v].cast<double>().dot((ctx.centres[c] - pv).normalized());
          if (std::abs(f) >= best) continue;
          // The contour (normal across the ray) passes between this vertex and
          // a neighbour facing the other way, nearer to this one.
          for (uint32_t nb : topo.ring[v]) {
            const Vector3d pn = p[nb].cast<double>();
            const double g = normals[nb].cast<double>().dot((ctx.centres[c] - pn).normalized());
            if ((f >= 0) != (g >= 0) && std::abs(f) <= std::abs(g)) {
              best = std::abs(f);
              contour_camera[v] = int(c);
              break;
            }
          }
        }
      });
    };
    find_contours();
    ShapeRefinementReport::Level stats;
    stats.range = range;
    for (uint32_t v : canon) {
      stats.stereo_matches += stereo[v].valid;
      stats.contour_vertices += contour_camera[v] >= 0;
      stats.outside_hull += !hull->Contains(p[v].cast<double>());
    }
    const int smoothing = int(std::lround(range / 0.005));
    std::vector<Vector3d> move(p.size(), Vector3d::Zero());
    std::vector<double> weight(p.size(), 0.0);
    for (int it = 0; it < o.iterations; ++it) {
      if (it > 0) {
        normals = VertexNormals(model.mesh.triangles, p, topo.welded);
        find_contours();
      }
      for_canonical([&](uint32_t v) {
        const Vector3d pv = p[v].cast<double>();
        Vector3d sum = Vector3d::Zero();
        double w = 0;
        // Silhouette: onto the hull from outside it; on a camera's contour,
        // onto that camera's silhouette outline (where the surface touches
        // the hull).
        Vector3d target;
        if (!hull->Contains(pv)) {
          // Only within the level's range, as the other terms search: a hull
          // surface further away is a hole in a silhouette or a pose off the
          // footage, not the shape (pulled there, limbs flew off by metres).
          hull_surface.Nearest(pv, &target);
          if ((target - pv).norm() <= range) {
            sum += o.silhouette_weight * (target - pv);
            w += o.silhouette_weight;
          }
        } else if (contour_camera[v] >= 0) {
          const int c = contour_camera[v];
          const Vector3d ray = (pv - ctx.centres[c]).normalized();
          const Vector3d nv = normals[v].cast<double>();
          const Vector3d across = (nv - nv.dot(ray) * ray).normalized();
          if (RimTarget(ctx, size_t(c), pv, across, range, &target)) {
            const double ws = o.silhouette_weight;
            sum += ws * (target - pv);
            w += ws;
          }
        }
        if (stereo[v].valid) {
          const double wt = o.stereo_weight * stereo[v].score;
          sum += wt * (stereo[v].point - pv);
          w += wt;
        }
        move[v] = w > 0 ? Vector3d(sum / w) : Vector3d::Zero();
        weight[v] = w;
      });
      // Spread the data terms over the surface: neighbours' moves, weighted.
      for (int pass = 0; pass < smoothing; ++pass) {
        std::vector<Vector3d> next(move);
        std::vector<double> next_w(weight);
        for_canonical([&](uint32_t v) {
          Vector3d sum = weight[v] * move[v];
          double w = weight[v];
          for (uint32_t nb : topo.ring[v]) sum += weight[nb] * move[nb], w += weight[nb];
          const double count = 1.0 + topo.ring[v].size();
          next[v] = w > 0 ? Vector3d(sum / w) : Vector3d::Zero();
          next_w[v] = w / count;
        });
        move.swap(next);
        weight.swap(next_w);
      }
      std::vector<Vector3f> next(p);
      for_canonical([&](uint32_t v) {
        const Vector3d pv = p[v].cast<double>();
        Vector3d reg = Vector3d::Zero();
        if (!local[v].empty()) {
          for (const LocalFrame& f : local[v]) reg += FromFrame(f, p);
          reg = reg / double(local[v].size()) - pv;
        }
        const double lambda = o.regularisation_weight;
        Vector3d step = (weight[v] * move[v] + lambda * reg) / (weight[v] + lambda);
        // No step beyond the level's range: where the local frames of a few
        // vertices degenerate, the regularisation's pull feeds on itself
        // (tracked poses on background-subtracted silhouettes sent vertices
        // 25 m off at the middle level and 20 km at the finest).
        if (step.norm() > range) step *= range / step.norm();
        next[v] = (pv + o.step * step).cast<float>();
      });
      for (size_t v = 0; v < p.size(); ++v) next[v] = next[topo.welded[v]];
      p.swap(next);
    }
    // No target lies further than the level's search range: no vertex moves
    // further over the level, and a level that moved the surface further
    // than that on average diverged (a pose off the footage, a hull with
    // holes) and is undone.
    double moved = 0;
    for (uint32_t v : canon) {
      const Vector3f d = p[v] - level_start[v];
      if (d.norm() > range) p[v] = level_start[v] + d * float(range / d.norm());
      moved += (p[v] - level_start[v]).norm();
    }
    for (size_t v = 0; v < p.size(); ++v) p[v] = p[topo.welded[v]];
    stats.mean_move = canon.empty() ? 0 : moved / canon.size();
    if (stats.mean_move > 0.5 * range) {
      p = level_start;
      stats.mean_move = 0;
      stats.dropped = 1;
    }
    if (report) {
      auto& l = report->levels[level];
      l.range = range;
      l.stereo_matches += stats.stereo_matches;
      l.contour_vertices += stats.contour_vertices;
      l.outside_hull += stats.outside_hull;
      l.mean_move += stats.mean_move;
      l.dropped += stats.dropped;
    }
  }
  *posed = std::move(p);
  return Status::Ok();
}

}  // namespace

Status RefinePosedShape(const BodyModel& model, const std::vector<Camera>& cameras,
                        const RefinementFrame& frame, const ShapeRefinementOptions& options,
                        std::vector<Vector3f>* posed, ShapeRefinementReport* report,
                        const ParallelRunner& runner) {
  const Topology topo = MakeTopology(model.mesh);
  return RefineFrame(model, cameras, frame, options, topo, posed, report, runner);
}

StatusOr<BodyModel> RefineShape(const BodyModel& model, const std::vector<Camera>& cameras,
                                const std::vector<RefinementFrame>& frames,
                                const ShapeRefinementOptions& o, ShapeRefinementReport* report,
                                const ParallelRunner& runner,
                                const std::function<void(const std::string&)>& progress) {
  const auto start = std::chrono::steady_clock::now();
  if (frames.empty()) return InvalidArgument("shape refinement: no frames");
  if (o.levels.empty() || o.iterations < 1 || !(o.step > 0 && o.step <= 1)) {
    return InvalidArgument("shape refinement: needs levels, iterations >= 1 and a step in (0, 1]");
  }
  const Topology topo = MakeTopology(model.mesh);
  std::vector<Vector3d> bind_sum(model.mesh.positions.size(), Vector3d::Zero());
  for (size_t i = 0; i < frames.size(); ++i) {
    std::vector<Vector3f> posed;
    FVV_RETURN_IF_ERROR(RefineFrame(model, cameras, frames[i], o, topo, &posed, report, runner));
    // Back to the bind pose through each vertex's own skinning transform.
    const std::vector<Eigen::Matrix4d> skin = BlendMatrices(model, frames[i].dofs);
    for (size_t v = 0; v < posed.size(); ++v) {
      const Eigen::Matrix3d a = skin[v].topLeftCorner<3, 3>();
      const Vector3d t = skin[v].topRightCorner<3, 1>();
      bind_sum[v] += a.inverse() * (posed[v].cast<double>() - t);
    }
    if (progress) {
      progress("refine: frame " + std::to_string(i + 1) + "/" + std::to_string(frames.size()));
    }
  }
  std::vector<Vector3f> bind(bind_sum.size());
  for (size_t v = 0; v < bind.size(); ++v)
    bind[v] = (bind_sum[v] / double(frames.size())).cast<float>();
  for (size_t v = 0; v < bind.size(); ++v) bind[v] = bind[topo.welded[v]];
  BodyModel refined = model;
  SetMeshPositions(bind, &refined.mesh);
  if (report) {
    for (auto& l : report->levels) l.mean_move /= double(frames.size());
    report->seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return refined;
}

}  // namespace fvv
