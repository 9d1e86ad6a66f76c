#include "encoder/track/pose_fitter.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "encoder/body/kinematics.h"
#include "encoder/capture/calibration.h"
#include "encoder/track/powell.h"
#include "encoder/track/silhouette_raster.h"

namespace fvv {
namespace {

using Eigen::Vector2f;
using Eigen::Vector3d;
using Eigen::Vector3f;

// The tracking mesh: the generic body's shape at a resolution whose
// silhouettes match the full model's to well under a pixel at the fine level.
const MeshResolution kTrackingMesh{10, 16};

struct Capsule {
  Vector3d a, b;
  double r;
};

double SegmentDistance(const Vector3d& p0, const Vector3d& p1, const Vector3d& q0,
                       const Vector3d& q1) {
  const Vector3d d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  double s = 0, t = 0;
  if (a < 1e-12 && e < 1e-12) return r.norm();
  if (a < 1e-12) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e < 1e-12) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2), denom = a * e - b * b;
      s = denom > 1e-12 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0) {
        t = 0, s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1) {
        t = 1, s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  return ((p0 + d1 * s) - (q0 + d2 * t)).norm();
}

}  // namespace

void FitView::SetCamera(const Camera& cam, int f) {
  factor = f;
  w = int(cam.width) / f, h = int(cam.height) / f;
  const float sc = 1.0f / f;
  r = CameraRotation(cam).cast<float>();
  t = CameraTranslation(cam).cast<float>();
  fx = float(cam.fx) * sc, fy = float(cam.fy) * sc;
  cx = (float(cam.cx) + 0.5f) * sc - 0.5f, cy = (float(cam.cy) + 0.5f) * sc - 0.5f;
  for (int i = 0; i < 5; ++i) k[i] = float(cam.distortion[i]);
  distorted = std::any_of(k.begin(), k.end(), [](float x) { return x != 0; });
}

Vector2f FitView::Project(const Vector3f& p) const {
  const Vector3f c = r * p + t;
  const float z = std::max(c.z(), 1e-4f);
  float x = c.x() / z, y = c.y() / z;
  if (distorted) {
    const float r2 = x * x + y * y, rad = 1 + r2 * (k[0] + r2 * (k[1] + r2 * k[4]));
    const float xd = x * rad + 2 * k[2] * x * y + k[3] * (r2 + 2 * x * x);
    const float yd = y * rad + k[2] * (r2 + 2 * y * y) + 2 * k[3] * x * y;
    x = xd, y = yd;
  }
  return {fx * x + cx, fy * y + cy};
}

int64_t FitView::IntegralSum(int x0, int y0, int x1, int y1) const {
  const int s = w + 1;
  return int64_t(xor_integral[size_t(y1 + 1) * s + x1 + 1]) -
         xor_integral[size_t(y0) * s + x1 + 1] - xor_integral[size_t(y1 + 1) * s + x0] +
         xor_integral[size_t(y0) * s + x0];
}

PoseFitter::PoseFitter(std::vector<Camera> c, const TrackerOptions& o)
    : options(o), cameras(std::move(c)), pool(std::max(1u, o.threads)) {
  BuildModel();
}

void PoseFitter::BuildModel() {
  model = MakeGenericBody(shape, kTrackingMesh);
  refs = model.skeleton.Dofs();
  lo.resize(refs.size()), hi.resize(refs.size());
  for (size_t d = 0; d < refs.size(); ++d) {
    lo[d] = model.skeleton.bones[refs[d].bone].dof_min[refs[d].kind];
    hi[d] = model.skeleton.bones[refs[d].bone].dof_max[refs[d].kind];
  }
  BuildStages();
}

// Stages and what each one moves: a vertex moves when any bone in the
// subtree of the stage's bones influences it.
void PoseFitter::BuildStages() {
  struct Spec {
    const char* name;
    std::vector<std::pair<int, int>> dofs;  // (bone, kind)
    int grid_a, grid_b, grid_c, twist;
  };
  const std::vector<Spec> specs = {
      {"torso",
       {{kRoot, 3},
        {kRoot, 4},
        {kRoot, 5},
        {kRoot, 0},
        {kRoot, 1},
        {kRoot, 2},
        {kLumbar, 0},
        {kLumbar, 2},
        {kThoracic, 1}},
       -1,
       -1,
       -1,
       -1},
      {"left arm",
       {{kLeftShoulder, 0}, {kLeftShoulder, 1}, {kLeftShoulder, 2}, {kLeftElbow, 1}},
       1,
       2,
       3,
       0},
      {"right arm",
       {{kRightShoulder, 0}, {kRightShoulder, 1}, {kRightShoulder, 2}, {kRightElbow, 1}},
       1,
       2,
       3,
       0},
      {"left leg", {{kLeftHip, 0}, {kLeftHip, 1}, {kLeftHip, 2}, {kLeftKnee, 0}}, 0, 2, 3, 1},
      {"right leg", {{kRightHip, 0}, {kRightHip, 1}, {kRightHip, 2}, {kRightKnee, 0}}, 0, 2, 3, 1},
      {"hands",
       {{kLeftWrist, 1}, {kLeftWrist, 2}, {kRightWrist, 1}, {kRightWrist, 2}},
       -1,
       -1,
       -1,
       -1},
      {"feet",
       {{kLeftAnkle, 0}, {kLeftAnkle, 2}, {kRightAnkle, 0}, {kRightAnkle, 2}},
       -1,
       -1,
       -1,
       -1},
      {"head", {{kNeck, 0}, {kHead, 1}}, -1, -1, -1, -1},
  };
  stages.clear();
  const Mesh& m = model.mesh;
  for (const Spec& sp : specs) {
    PoseStage st;
    st.name = sp.name;
    std::vector<char> moved(model.skeleton.bones.size(), 0);
    for (const auto& [bone, kind] : sp.dofs) {
      st.dofs.push_back(Dof(bone, kind));
      moved[bone] = 1;
    }
    for (size_t b = 0; b < moved.size(); ++b) {  // parents come first
      const int p = model.skeleton.bones[b].parent;
      if (p >= 0 && moved[p]) moved[b] = 1;
    }
    std::vector<char> vmove(m.positions.size(), 0);
    for (size_t v = 0; v < m.positions.size(); ++v) {
      for (int k = 0; k < kMaxInfluences; ++k) {
        if (m.weights[v][k] && moved[m.joints[v][k]]) vmove[v] = 1;
      }
    }
    // Triangles with any moving vertex are redrawn; every vertex they use is
    // skinned and projected (including ones that do not move themselves).
    std::vector<char> used(m.positions.size(), 0);
    for (const auto& t : m.triangles) {
      const bool moves = vmove[t[0]] || vmove[t[1]] || vmove[t[2]];
      auto& list = moves ? st.moving_tris : st.fixed_tris;
      list.insert(list.end(), t.begin(), t.end());
      if (moves) used[t[0]] = used[t[1]] = used[t[2]] = 1;
    }
    for (size_t v = 0; v < m.positions.size(); ++v) {
      if (used[v]) st.moving_verts.push_back(uint32_t(v));
    }
    st.grid_dof_a = sp.grid_a, st.grid_dof_b = sp.grid_b, st.grid_dof_c = sp.grid_c;
    st.twist = sp.twist;
    stages.push_back(std::move(st));
  }
  trunk = PoseStage();
  trunk.name = "trunk";
  trunk.dofs = stages[kTorsoStage].dofs;
  auto in_trunk = [&](uint32_t v) {
    const int seg = m.segments[v];
    return seg == kSegPelvis || seg == kSegAbdomen || seg == kSegChest || seg == kSegHead;
  };
  std::vector<char> used(m.positions.size(), 0);
  for (const auto& t : m.triangles) {
    if (!in_trunk(t[0]) || !in_trunk(t[1]) || !in_trunk(t[2])) continue;
    trunk.moving_tris.insert(trunk.moving_tris.end(), t.begin(), t.end());
    used[t[0]] = used[t[1]] = used[t[2]] = 1;
  }
  for (size_t v = 0; v < m.positions.size(); ++v) {
    if (used[v]) trunk.moving_verts.push_back(uint32_t(v));
  }
}

Status PoseFitter::SetFrame(const std::vector<Image>& silhouettes,
                            const std::vector<std::vector<JointSighting>>& sightings, int* usable) {
  if (silhouettes.size() != cameras.size()) {
    return InvalidArgument("tracker: " + std::to_string(silhouettes.size()) + " silhouettes for " +
                           std::to_string(cameras.size()) + " cameras");
  }
  if (!sightings.empty() && sightings.size() != cameras.size()) {
    return InvalidArgument("tracker: joint sightings for " + std::to_string(sightings.size()) +
                           " cameras, not " + std::to_string(cameras.size()));
  }
  *usable = 0;
  const int factors[2] = {2 * fine_factor, fine_factor};
  views.assign(2, std::vector<FitView>(cameras.size()));
  actor_px.assign(cameras.size(), 0.0);
  for (size_t c = 0; c < cameras.size(); ++c) {
    const Camera& cam = cameras[c];
    const Image& s = silhouettes[c];
    if (s.width != cam.width || s.height != cam.height || s.channels != 1) {
      return InvalidArgument("tracker: silhouette of camera \"" + cam.name + "\" is not a " +
                             std::to_string(cam.width) + "x" + std::to_string(cam.height) +
                             " grey image");
    }
    for (int level = 0; level < 2; ++level) {
      FitView& v = views[level][c];
      const int f = factors[level];
      v.SetCamera(cam, f);
      v.sil.assign(size_t(v.w) * v.h, 0);
      v.sil_area = 0;
      int top = v.h, bottom = -1;
      for (int y = 0; y < v.h; ++y) {
        for (int x = 0; x < v.w; ++x) {
          int count = 0;
          for (int dy = 0; dy < f; ++dy) {
            const uint8_t* row = &s.pixels[size_t(y * f + dy) * s.width + size_t(x) * f];
            for (int dx = 0; dx < f; ++dx) count += row[dx] != 0;
          }
          const bool on = 2 * count >= f * f;
          v.sil[size_t(y) * v.w + x] = on;
          v.sil_area += on;
          if (on) top = std::min(top, y), bottom = y;
        }
      }
      if (level == kFine && bottom >= 0) actor_px[c] = double(bottom - top + 1) * f;
      v.fixed.assign(v.sil.size(), 0);
      v.scratch.assign(v.sil.size(), 0);
      v.xor_integral.assign(size_t(v.w + 1) * (v.h + 1), 0);
    }
    if (views[kFine][c].sil_area > 0) ++*usable;
  }
  joints.assign(cameras.size(), {});
  for (size_t c = 0; c < sightings.size(); ++c) {
    for (const JointSighting& j : sightings[c]) {
      if (j.joint < 0 || j.joint >= kGenericJointCount || !(j.confidence > 0) ||
          !j.pixel.allFinite()) {
        continue;
      }
      joints[c].push_back(j);
    }
    // Sightings without a silhouette to size them by are left out: the
    // term's scale would be a guess.
    if (actor_px[c] <= 0) joints[c].clear();
  }
  return Status::Ok();
}

std::vector<Eigen::Matrix4f> PoseFitter::Skinning(const std::vector<double>& dofs) const {
  std::vector<Eigen::Matrix4f> out;
  for (const Affine& a : SkinningMatrices(model.skeleton, dofs))
    out.push_back(a.matrix().cast<float>());
  return out;
}

void PoseFitter::SkinVertices(const std::vector<uint32_t>& verts,
                              const std::vector<Eigen::Matrix4f>& skin,
                              std::vector<Vector3f>* out) const {
  const Mesh& m = model.mesh;
  out->resize(m.positions.size());
  for (uint32_t v : verts) {
    Eigen::Matrix4f s = Eigen::Matrix4f::Zero();
    for (int k = 0; k < kMaxInfluences; ++k) {
      if (m.weights[v][k]) s += (m.weights[v][k] / 65535.0f) * skin[m.joints[v][k]];
    }
    (*out)[v] = s.topLeftCorner<3, 3>() *
                    Vector3f(m.positions[v][0], m.positions[v][1], m.positions[v][2]) +
                s.topRightCorner<3, 1>();
  }
}

// Draws the fixed parts of `stage` at `dofs` into every view of `level`.
void PoseFitter::PrepareStage(const PoseStage& stage, const std::vector<double>& dofs, int level) {
  std::vector<uint32_t> all(model.mesh.positions.size());
  std::iota(all.begin(), all.end(), 0u);
  std::vector<Vector3f> posed;
  SkinVertices(all, Skinning(dofs), &posed);
  pool.Run(uint32_t(cameras.size()), [&](uint32_t c) {
    FitView& v = views[level][c];
    std::fill(v.fixed.begin(), v.fixed.end(), 0);
    std::vector<Vector2f> px(posed.size());
    for (size_t i = 0; i < posed.size(); ++i) px[i] = v.Project(posed[i]);
    RasterBox box{v.w, v.h, -1, -1};
    RasteriseSilhouette(stage.fixed_tris, px, v.w, v.h, v.fixed.data(), &box);
    const int s = v.w + 1;
    v.xor_total = 0;
    for (int y = 0; y < v.h; ++y) {
      int32_t row = 0;
      for (int x = 0; x < v.w; ++x) {
        const size_t i = size_t(y) * v.w + x;
        row += v.fixed[i] ^ v.sil[i];
        v.xor_integral[size_t(y + 1) * s + x + 1] = v.xor_integral[size_t(y) * s + x + 1] + row;
      }
      v.xor_total += row;
    }
  });
}

// Capsule overlap of forearms and hands with the torso, and of the legs
// with each other, in metres (0 when nothing interpenetrates).
double PoseFitter::Overlap(const std::vector<double>& dofs) const {
  const std::vector<Vector3d> j = JointPositions(model.skeleton, dofs);
  const double g = shape.stature;
  auto tip = [&](int from, int to, double len) {
    return Vector3d(j[to] + (j[to] - j[from]).normalized() * len * g);
  };
  const Capsule torso{j[kRoot], j[kNeck], 0.1 * g};
  const Capsule arms[] = {{j[kLeftElbow], j[kLeftWrist], 0.03 * g},
                          {j[kLeftWrist], tip(kLeftElbow, kLeftWrist, 0.12), 0.025 * g},
                          {j[kRightElbow], j[kRightWrist], 0.03 * g},
                          {j[kRightWrist], tip(kRightElbow, kRightWrist, 0.12), 0.025 * g}};
  const Capsule left[] = {{j[kLeftHip], j[kLeftKnee], 0.06 * g},
                          {j[kLeftKnee], j[kLeftAnkle], 0.04 * g}};
  const Capsule right[] = {{j[kRightHip], j[kRightKnee], 0.06 * g},
                           {j[kRightKnee], j[kRightAnkle], 0.04 * g}};
  double overlap = 0;
  auto add = [&](const Capsule& a, const Capsule& b) {
    overlap += std::max(0.0, a.r + b.r - SegmentDistance(a.a, a.b, b.a, b.b));
  };
  for (const Capsule& a : arms) add(a, torso);
  for (const Capsule& a : left) {
    for (const Capsule& b : right) add(a, b);
  }
  return overlap;
}

double PoseFitter::Evaluate(const PoseStage& stage, const std::vector<double>& dofs, int level) {
  ++evaluations;
  std::vector<Vector3f> posed;
  SkinVertices(stage.moving_verts, Skinning(dofs), &posed);
  std::vector<int64_t> per_camera(cameras.size(), 0);
  pool.Run(uint32_t(cameras.size()), [&](uint32_t c) {
    FitView& v = views[level][c];
    std::vector<Vector2f>& px = v.projected;  // only the moving vertices are read
    if (px.size() < posed.size()) px.resize(posed.size());
    for (uint32_t i : stage.moving_verts) px[i] = v.Project(posed[i]);
    RasterBox box{v.w, v.h, -1, -1};
    // Clear the scratch where the last evaluation may have drawn: the whole
    // image is cheap at these sizes only once; afterwards by box.
    RasteriseSilhouette(stage.moving_tris, px, v.w, v.h, v.scratch.data(), &box);
    if (box.x0 > box.x1) {
      per_camera[c] = v.xor_total;
      return;
    }
    int64_t count = 0;
    for (int y = box.y0; y <= box.y1; ++y) {
      const size_t row = size_t(y) * v.w;
      for (int x = box.x0; x <= box.x1; ++x) {
        count += (v.fixed[row + x] | v.scratch[row + x]) ^ v.sil[row + x];
        v.scratch[row + x] = 0;
      }
    }
    per_camera[c] = v.xor_total - v.IntegralSum(box.x0, box.y0, box.x1, box.y1) + count;
  });
  double total = 0;
  for (size_t c = 0; c < cameras.size(); ++c) {
    if (views[level][c].sil_area > 0) total += double(per_camera[c]);
  }
  double prior = 0;
  if (!prediction.empty()) {
    for (int d : stage.dofs) {
      if (refs[d].kind < 3) prior += (dofs[d] - prediction[d]) * (dofs[d] - prediction[d]);
    }
  }
  return total + KeypointCost(dofs, level) +
         (1 << (2 * level)) * (collision_weight * Overlap(dofs) + smoothness_weight * prior);
}

double PoseFitter::EvaluateBody(const std::vector<double>& dofs) {
  PrepareStage(stages[kTorsoStage], dofs, kFine);
  return Evaluate(stages[kTorsoStage], dofs, kFine);
}

// Each sighting's error is its distance from the model's joint in shares of
// the actor's height in that image, e; it costs c e^2 / (1 + e^2 / t^2) with
// c its confidence: quadratic near the joint, and a wrong sighting (another
// person's, a left-right swap) costs at most c t^2.
double PoseFitter::KeypointCost(const std::vector<double>& dofs, int level) const {
  if (keypoint_weight.empty()) return 0;
  const double t2 = options.keypoint_reach * options.keypoint_reach;
  std::vector<Vector3d> world;
  double total = 0;
  for (size_t c = 0; c < cameras.size(); ++c) {
    if (joints[c].empty()) continue;
    if (world.empty()) world = JointPositions(model.skeleton, dofs);
    const FitView& v = views[level][c];
    double sum = 0;
    for (const JointSighting& j : joints[c]) {
      const Vector2f p = v.Project(world[j.joint].cast<float>());
      // Back to full-resolution pixels (pixel centres kept).
      const Eigen::Vector2d full((p.x() + 0.5) * v.factor - 0.5, (p.y() + 0.5) * v.factor - 0.5);
      const double e2 = (full - j.pixel).squaredNorm() / (actor_px[c] * actor_px[c]);
      sum += j.confidence * e2 / (1 + e2 / t2);
    }
    total += keypoint_weight[c] * double(1 << (2 * level)) * sum;
  }
  return total;
}

double PoseFitter::KeypointDistance(const std::vector<double>& dofs) const {
  std::vector<Vector3d> world;
  double sum = 0;
  int n = 0;
  for (size_t c = 0; c < cameras.size(); ++c) {
    for (const JointSighting& j : joints[c]) {
      if (j.confidence < 0.5) continue;
      if (world.empty()) world = JointPositions(model.skeleton, dofs);
      Eigen::Vector2d p;
      if (!ProjectPoint(cameras[c], world[j.joint], &p)) continue;
      sum += (p - j.pixel).norm() / actor_px[c];
      ++n;
    }
  }
  return n ? sum / n : -1;
}

void PoseFitter::SetWeights() {
  int64_t area = 0;
  for (const FitView& v : views[kCoarse]) area += v.sil_area;
  collision_weight = 0.5 * double(area) / 0.01 / 8;  // about a twentieth of the body per cm
  smoothness_weight = options.smoothness * double(area);
  keypoint_weight.clear();
  bool any = false;
  for (const auto& j : joints) any = any || !j.empty();
  if (!any || options.keypoint_weight <= 0) return;
  // In pixels of the coarse level, as the penalties: a camera's term scales
  // with its silhouette area, as its XOR does.
  for (const FitView& v : views[kCoarse]) {
    keypoint_weight.push_back(options.keypoint_weight * double(v.sil_area));
  }
}

double PoseFitter::FitStage(const PoseStage& stage, std::vector<double>* dofs, int level,
                            double scale, Grid grid) {
  PrepareStage(stage, *dofs, level);
  const int n = int(stage.dofs.size());
  Eigen::VectorXd x(n), step(n), vlo(n), vhi(n);
  for (int i = 0; i < n; ++i) {
    const int d = stage.dofs[i];
    x[i] = (*dofs)[d];
    const bool translation = refs[d].kind >= 3;
    step[i] = (translation ? 0.03 : 0.12) * scale;
    vlo[i] = lo[d], vhi[i] = hi[d];
  }
  std::vector<double> trial = *dofs;
  auto f = [&](const Eigen::VectorXd& v) {
    for (int i = 0; i < n; ++i) trial[stage.dofs[i]] = v[i];
    return Evaluate(stage, trial, level);
  };
  if (stage.grid_dof_a >= 0 && grid != Grid::kNone) {
    // A limited grid over the upper joint's two main angles and the hinge, so
    // the search starts in the right basin; wide (absolute angles) when
    // nothing is known yet, narrow around the prediction while tracking.
    const bool wide = grid == Grid::kWide;
    const std::vector<double> as = wide ? std::vector<double>{-1.0, -0.5, 0.0, 0.5, 1.0}
                                        : std::vector<double>{-0.35, 0.0, 0.35};
    const std::vector<double> bs = wide ? std::vector<double>{-1.6, -0.8, 0.0, 0.8, 1.6}
                                        : std::vector<double>{-0.35, 0.0, 0.35};
    const std::vector<double> cs =
        wide ? std::vector<double>{-1.4, 0.0, 1.4} : std::vector<double>{-0.6, 0.0, 0.6};
    Eigen::VectorXd best = x;
    double best_value = f(x);
    const std::vector<double> twists =
        wide && stage.twist >= 0 ? std::vector<double>{-0.8, 0.0, 0.8} : std::vector<double>{0.0};
    for (double da : as) {
      for (double db : bs) {
        for (double dc : cs) {
          for (double tw : twists) {
            Eigen::VectorXd g = x;
            if (wide && stage.twist >= 0) g[stage.twist] = tw;
            g[stage.grid_dof_a] = (wide ? 0.0 : x[stage.grid_dof_a]) + da;
            g[stage.grid_dof_b] = (wide ? 0.0 : x[stage.grid_dof_b]) + db;
            g[stage.grid_dof_c] = (wide ? 0.0 : x[stage.grid_dof_c]) + dc;
            g = g.cwiseMax(vlo).cwiseMin(vhi);
            const double value = f(g);
            if (value < best_value) best_value = value, best = g;
          }
        }
      }
    }
    x = best;
  }
  PowellOptions po;
  po.max_evaluations = options.stage_evaluations;
  const PowellResult r = MinimisePowell(f, &x, step, vlo, vhi, po);
  for (int i = 0; i < n; ++i) (*dofs)[stage.dofs[i]] = x[i];
  return r.value;
}

void PoseFitter::FitAll(std::vector<double>* dofs, double scale, Grid grid) {
  for (int level = 0; level < (options.refine ? 2 : 1); ++level) {
    for (const PoseStage& s : stages) {
      FitStage(s, dofs, level, level == 0 ? scale : 0.35 * scale, level == 0 ? grid : Grid::kNone);
    }
  }
}

// The legs' angles exchanged, left for right: the other phase of a stride.
// A fit can reach each foot with the other leg, the legs crossed (one
// forward and one back, they never touch), and stay there: the narrow
// searches move a leg a little at a time, and prediction carries the
// crossing on to the next frames.
std::vector<double> PoseFitter::LegsExchanged(const std::vector<double>& dofs) const {
  std::vector<double> out = dofs;
  const std::pair<int, int> pairs[] = {
      {kLeftHip, kRightHip}, {kLeftKnee, kRightKnee}, {kLeftAnkle, kRightAnkle}};
  for (const auto& [l, r] : pairs) {
    for (int kind = 0; kind < 3; ++kind) {
      const int dl = Dof(l, kind), dr = Dof(r, kind);
      if (dl < 0 || dr < 0) continue;
      out[dl] = std::clamp(dofs[dr], lo[dl], hi[dl]);
      out[dr] = std::clamp(dofs[dl], lo[dr], hi[dr]);
    }
  }
  return out;
}

// Both legs fitted again from their exchanged angles, kept where the whole
// body's objective at the fine level is at least 5 % lower: a crossing shows as
// far more (11-19 % on CesiumMan), and near-ties are left alone.
void PoseFitter::TryLegsExchanged(std::vector<double>* dofs) {
  if (!options.exchange_legs) return;
  std::vector<double> trial = LegsExchanged(*dofs);
  for (int level = 0; level < 2; ++level) {
    for (StageId st : {kLeftLegStage, kRightLegStage}) {
      FitStage(stages[st], &trial, level, level ? 0.35 : 0.5, level ? Grid::kNone : Grid::kNarrow);
    }
  }
  KeepIfFitsBetter(dofs, trial, 0.95);
}

void PoseFitter::KeepIfFitsBetter(std::vector<double>* dofs, const std::vector<double>& trial,
                                  double factor) {
  const double before = EvaluateBody(*dofs);
  if (Evaluate(stages[kTorsoStage], trial, kFine) < factor * before) *dofs = trial;
}

// A limb can move further in one frame than the narrow search reaches: when
// the fit is poor, each limb is searched again from a wide grid of absolute
// angles, and the result kept where it lowers the whole body's XOR.
void PoseFitter::Recover(std::vector<double>* dofs, FrameFit* fit) {
  for (StageId s : {kLeftArmStage, kRightArmStage, kLeftLegStage, kRightLegStage}) {
    std::vector<double> trial = *dofs;
    FitStage(stages[s], &trial, kCoarse, 1.0, Grid::kWide);
    FitStage(stages[s], &trial, kFine, 0.35, Grid::kNone);
    KeepIfFitsBetter(dofs, trial, 1.0);
  }
  TryLegsExchanged(dofs);
  FitStage(stages[kTorsoStage], dofs, kFine, 0.35, Grid::kNone);
  Measure(*dofs, fit);
}

void PoseFitter::Measure(const std::vector<double>& dofs, FrameFit* fit) {
  PoseStage all;
  all.moving_verts.resize(model.mesh.positions.size());
  std::iota(all.moving_verts.begin(), all.moving_verts.end(), 0u);
  for (const auto& t : model.mesh.triangles)
    all.moving_tris.insert(all.moving_tris.end(), t.begin(), t.end());
  std::vector<Vector3f> posed;
  SkinVertices(all.moving_verts, Skinning(dofs), &posed);
  int64_t inter = 0, uni = 0, area = 0;
  fit->cameras_used = 0;
  for (FitView& v : views[kFine]) {
    if (v.sil_area == 0) continue;
    ++fit->cameras_used;
    std::vector<Vector2f> px(posed.size());
    for (size_t i = 0; i < posed.size(); ++i) px[i] = v.Project(posed[i]);
    std::vector<uint8_t> m(v.sil.size(), 0);
    RasterBox box{v.w, v.h, -1, -1};
    RasteriseSilhouette(all.moving_tris, px, v.w, v.h, m.data(), &box);
    for (size_t i = 0; i < m.size(); ++i) inter += m[i] & v.sil[i], uni += m[i] | v.sil[i];
    area += v.sil_area;
  }
  fit->iou = uni ? double(inter) / uni : 0;
  fit->xor_ratio = area ? double(uni - inter) / area : 1;
  fit->dofs = dofs;
  fit->keypoint_distance = KeypointDistance(dofs);
  fit->poor = fit->xor_ratio > options.poor_fit;
  if (fit->poor) {
    fit->note =
        "poor fit (XOR " + std::to_string(int(100 * fit->xor_ratio)) + "% of the silhouette)";
  } else if (fit->keypoint_distance > options.keypoint_disagreement) {
    fit->poor = true;
    fit->note = "disagrees with the keypoints (" +
                std::to_string(int(std::lround(100 * fit->keypoint_distance))) +
                "% of the actor's height off)";
  }
}
}  // namespace fvv
