#include "encoder/track/tracker.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numeric>

#include "codec/base/thread_pool.h"
#include "encoder/body/kinematics.h"
#include "encoder/capture/calibration.h"
#include "encoder/track/powell.h"
#include "encoder/track/silhouette_raster.h"

namespace fvv {
namespace {

using Eigen::Vector2f;
using Eigen::Vector3d;
using Eigen::Vector3f;

constexpr double kPi = 3.14159265358979323846;
// The tracking mesh: the generic body's shape at a resolution whose
// silhouettes match the full model's to well under a pixel at half resolution.
const MeshResolution kTrackingMesh{10, 16};

// One camera at one resolution: its scaled calibration, silhouette, and the
// per-stage raster of the parts that stay fixed.
struct View {
  int w = 0, h = 0;
  Eigen::Matrix3f r;
  Vector3f t;
  float fx = 0, fy = 0, cx = 0, cy = 0;
  std::array<float, 5> k{};
  bool distorted = false;
  std::vector<uint8_t> sil;  // 0/1
  int64_t sil_area = 0;
  std::vector<uint8_t> fixed, scratch;
  std::vector<Vector2f> projected;    // per-evaluation vertex positions, kept to spare allocations
  std::vector<int32_t> xor_integral;  // (w + 1) x (h + 1) prefix sums of fixed ^ sil
  int64_t xor_total = 0;

  Vector2f Project(const Vector3f& p) const {
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
  int64_t IntegralSum(int x0, int y0, int x1, int y1) const {  // inclusive box
    const int s = w + 1;
    return int64_t(xor_integral[size_t(y1 + 1) * s + x1 + 1]) -
           xor_integral[size_t(y0) * s + x1 + 1] - xor_integral[size_t(y1 + 1) * s + x0] +
           xor_integral[size_t(y0) * s + x0];
  }
};

// A set of DOFs optimised together, and what moves when they change.
struct Stage {
  std::string name;
  std::vector<int> dofs;               // indices into the DOF vector
  std::vector<uint32_t> moving_verts;  // vertices any moved bone influences
  std::vector<uint32_t> moving_tris, fixed_tris;
  int grid_dof_a = -1, grid_dof_b = -1, grid_dof_c = -1;  // grid search (indices into dofs)
  int twist = -1;  // the upper joint's twist: reset by a wide grid search
};

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

struct Tracker::Impl {
  TrackerOptions options;
  std::vector<Camera> cameras;
  ThreadPool pool;
  BodyShape shape;
  BodyModel model;  // tracking resolution
  std::vector<DofRef> refs;
  std::vector<double> lo, hi;
  std::vector<Stage> stages;
  // The torso stage's DOFs with only the trunk drawn (pelvis to head): the
  // heading search at initialisation, which the limbs would mislead.
  Stage trunk;
  // views[level][camera]; level 0 = quarter, 1 = half resolution.
  std::vector<std::vector<View>> views;
  std::vector<double> last, previous;
  bool initialised = false;
  int evaluations = 0;
  double collision_weight = 0;  // pixels per metre of capsule overlap
  // A weak pull towards the predicted pose (pixels per squared radian) that
  // decides between poses whose silhouettes are nearly alike (a forearm
  // hidden in front of the torso); empty while initialising.
  std::vector<double> prediction;
  double smoothness_weight = 0;
  // The actor's height measured from the silhouettes at initialisation.
  double actor_height = 0;
  // An actor fitted with proportions of its own has its arms' length fitted
  // again over several frames once tracking has moved them (KeptFrame).
  bool own_proportions = false;
  struct KeptFrame {
    std::vector<std::vector<View>> views;
    std::vector<double> dofs;
  };
  std::vector<KeptFrame> kept;
  int frames_tracked = 0;
  bool arms_refitted = false;

  explicit Impl(const TrackerOptions& o) : options(o), pool(std::max(1u, o.threads)) {}

  int Dof(int bone, int kind) const { return DofIndex(model.skeleton, bone, kind); }

  void BuildModel() {
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
  void BuildStages() {
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
        {"right leg",
         {{kRightHip, 0}, {kRightHip, 1}, {kRightHip, 2}, {kRightKnee, 0}},
         0,
         2,
         3,
         1},
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
      Stage st;
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
    trunk = Stage();
    trunk.name = "trunk";
    trunk.dofs = stages[0].dofs;
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

  Status SetSilhouettes(const std::vector<Image>& silhouettes, int* usable) {
    if (silhouettes.size() != cameras.size()) {
      return InvalidArgument("tracker: " + std::to_string(silhouettes.size()) +
                             " silhouettes for " + std::to_string(cameras.size()) + " cameras");
    }
    *usable = 0;
    const float scales[2] = {0.25f, 0.5f};
    views.assign(2, std::vector<View>(cameras.size()));
    for (size_t c = 0; c < cameras.size(); ++c) {
      const Camera& cam = cameras[c];
      const Image& s = silhouettes[c];
      if (s.width != cam.width || s.height != cam.height || s.channels != 1) {
        return InvalidArgument("tracker: silhouette of camera \"" + cam.name + "\" is not a " +
                               std::to_string(cam.width) + "x" + std::to_string(cam.height) +
                               " grey image");
      }
      for (int level = 0; level < 2; ++level) {
        View& v = views[level][c];
        const int f = int(std::lround(1 / scales[level]));
        v.w = int(cam.width) / f, v.h = int(cam.height) / f;
        const float sc = 1.0f / f;
        v.r = CameraRotation(cam).cast<float>();
        v.t = CameraTranslation(cam).cast<float>();
        v.fx = float(cam.fx) * sc, v.fy = float(cam.fy) * sc;
        v.cx = (float(cam.cx) + 0.5f) * sc - 0.5f, v.cy = (float(cam.cy) + 0.5f) * sc - 0.5f;
        for (int i = 0; i < 5; ++i) v.k[i] = float(cam.distortion[i]);
        v.distorted = std::any_of(v.k.begin(), v.k.end(), [](float x) { return x != 0; });
        v.sil.assign(size_t(v.w) * v.h, 0);
        v.sil_area = 0;
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
          }
        }
        v.fixed.assign(v.sil.size(), 0);
        v.scratch.assign(v.sil.size(), 0);
        v.xor_integral.assign(size_t(v.w + 1) * (v.h + 1), 0);
      }
      if (views[1][c].sil_area > 0) ++*usable;
    }
    return Status::Ok();
  }

  std::vector<Eigen::Matrix4f> Skinning(const std::vector<double>& dofs) const {
    std::vector<Eigen::Matrix4f> out;
    for (const Affine& a : SkinningMatrices(model.skeleton, dofs))
      out.push_back(a.matrix().cast<float>());
    return out;
  }

  void SkinVertices(const std::vector<uint32_t>& verts, const std::vector<Eigen::Matrix4f>& skin,
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
  void PrepareStage(const Stage& stage, const std::vector<double>& dofs, int level) {
    std::vector<uint32_t> all(model.mesh.positions.size());
    std::iota(all.begin(), all.end(), 0u);
    std::vector<Vector3f> posed;
    SkinVertices(all, Skinning(dofs), &posed);
    pool.Run(uint32_t(cameras.size()), [&](uint32_t c) {
      View& v = views[level][c];
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
  double Overlap(const std::vector<double>& dofs) const {
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

  // XOR pixels of the model at `dofs` against the silhouettes of `level`,
  // redrawing only `stage`'s moving parts, plus the collision penalty.
  double Evaluate(const Stage& stage, const std::vector<double>& dofs, int level) {
    ++evaluations;
    std::vector<Vector3f> posed;
    SkinVertices(stage.moving_verts, Skinning(dofs), &posed);
    std::vector<int64_t> per_camera(cameras.size(), 0);
    pool.Run(uint32_t(cameras.size()), [&](uint32_t c) {
      View& v = views[level][c];
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
    return total +
           (1 << (2 * level)) * (collision_weight * Overlap(dofs) + smoothness_weight * prior);
  }

  void SetCollisionWeight() {
    int64_t area = 0;
    for (const View& v : views[0]) area += v.sil_area;
    collision_weight = 0.5 * double(area) / 0.01 / 8;  // about a twentieth of the body per cm
    smoothness_weight = options.smoothness * double(area);
  }

  // Powell over one stage's DOFs, after an optional grid search.
  enum class Grid { kNone, kNarrow, kWide };
  double FitStage(const Stage& stage, std::vector<double>* dofs, int level, double scale,
                  Grid grid = Grid::kNone) {
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

  void FitAll(std::vector<double>* dofs, double scale, Grid grid) {
    for (int level = 0; level < (options.refine ? 2 : 1); ++level) {
      for (const Stage& s : stages) {
        FitStage(s, dofs, level, level == 0 ? scale : 0.35 * scale,
                 level == 0 ? grid : Grid::kNone);
      }
    }
  }

  // The legs' angles exchanged, left for right: the other phase of a stride.
  // A fit can reach each foot with the other leg, the legs crossed (one
  // forward and one back, they never touch), and stay there: the narrow
  // searches move a leg a little at a time, and prediction carries the
  // crossing on to the next frames.
  std::vector<double> LegsExchanged(const std::vector<double>& dofs) const {
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
  // body's XOR at half resolution is at least 5 % lower: a crossing shows as
  // far more (11-19 % on CesiumMan), and near-ties are left alone.
  void TryLegsExchanged(std::vector<double>* dofs) {
    if (!options.exchange_legs) return;
    std::vector<double> trial = LegsExchanged(*dofs);
    for (int level = 0; level < 2; ++level) {
      for (size_t st : {size_t{3}, size_t{4}}) {
        FitStage(stages[st], &trial, level, level ? 0.35 : 0.5,
                 level ? Grid::kNone : Grid::kNarrow);
      }
    }
    KeepIfFitsBetter(dofs, trial, 0.95);
  }

  // Replaces *dofs by `trial` where the whole body's XOR at half resolution
  // is below `factor` times that of *dofs.
  void KeepIfFitsBetter(std::vector<double>* dofs, const std::vector<double>& trial,
                        double factor) {
    PrepareStage(stages[0], *dofs, 1);
    const double before = Evaluate(stages[0], *dofs, 1);
    if (Evaluate(stages[0], trial, 1) < factor * before) *dofs = trial;
  }

  // A limb can move further in one frame than the narrow search reaches: when
  // the fit is poor, each limb is searched again from a wide grid of absolute
  // angles, and the result kept where it lowers the whole body's XOR.
  void Recover(std::vector<double>* dofs, FrameFit* fit) {
    for (size_t s = 1; s <= 4; ++s) {
      std::vector<double> trial = *dofs;
      FitStage(stages[s], &trial, 0, 1.0, Grid::kWide);
      FitStage(stages[s], &trial, 1, 0.35, Grid::kNone);
      KeepIfFitsBetter(dofs, trial, 1.0);
    }
    TryLegsExchanged(dofs);
    FitStage(stages[0], dofs, 1, 0.35, Grid::kNone);
    Measure(*dofs, fit);
  }

  // Quality at half resolution, from a full redraw.
  void Measure(const std::vector<double>& dofs, FrameFit* fit) {
    Stage all;
    all.moving_verts.resize(model.mesh.positions.size());
    std::iota(all.moving_verts.begin(), all.moving_verts.end(), 0u);
    for (const auto& t : model.mesh.triangles)
      all.moving_tris.insert(all.moving_tris.end(), t.begin(), t.end());
    std::vector<Vector3f> posed;
    SkinVertices(all.moving_verts, Skinning(dofs), &posed);
    int64_t inter = 0, uni = 0, area = 0;
    fit->cameras_used = 0;
    for (View& v : views[1]) {
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
    fit->poor = fit->xor_ratio > options.poor_fit;
    if (fit->poor)
      fit->note =
          "poor fit (XOR " + std::to_string(int(100 * fit->xor_ratio)) + "% of the silhouette)";
  }

  // A rough global position and height from the silhouettes' geometry: the
  // point nearest all rays through the silhouette centroids, and the top of
  // the silhouettes above it.
  bool Locate(const std::vector<Image>& sils, Vector3d* centre, double* height) {
    Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
    Vector3d b = Vector3d::Zero();
    int rays = 0;
    std::vector<std::pair<const Camera*, Eigen::Vector2d>> tops;
    for (size_t c = 0; c < cameras.size(); ++c) {
      const Image& s = sils[c];
      double sx = 0, sy = 0;
      int64_t n = 0;
      int top = -1, top_x = 0;
      for (uint32_t y = 0; y < s.height; ++y) {
        for (uint32_t x = 0; x < s.width; ++x) {
          if (!s.pixels[size_t(y) * s.width + x]) continue;
          sx += x, sy += y, ++n;
          if (top < 0) top = int(y), top_x = int(x);
        }
      }
      if (n == 0) continue;
      const Vector3d o = CameraCentre(cameras[c]);
      const Vector3d d = (UnprojectPixel(cameras[c], {sx / n, sy / n}, 1.0) - o).normalized();
      const Eigen::Matrix3d p = Eigen::Matrix3d::Identity() - d * d.transpose();
      a += p, b += p * o, ++rays;
      tops.push_back({&cameras[c], Eigen::Vector2d(top_x, top)});
    }
    if (rays < 2) return false;
    *centre = a.ldlt().solve(b);
    std::vector<double> heights;
    for (const auto& [cam, px] : tops) {
      // The top pixel's ray, at the depth of the vertical through the centre.
      const Vector3d o = CameraCentre(*cam);
      const Vector3d d = (UnprojectPixel(*cam, px, 1.0) - o).normalized();
      const Eigen::Vector2d flat(d.x(), d.z());
      const double along =
          flat.squaredNorm() > 1e-9
              ? Eigen::Vector2d(centre->x() - o.x(), centre->z() - o.z()).dot(flat) /
                    flat.squaredNorm()
              : 0;
      heights.push_back(o.y() + along * d.y());
    }
    std::nth_element(heights.begin(), heights.begin() + heights.size() / 2, heights.end());
    *height = heights[heights.size() / 2];
    return true;
  }

  std::vector<double> NeutralPose(const Vector3d& centre, double yaw) const {
    std::vector<double> p(refs.size(), 0.0);
    const std::vector<Vector3d> rest = JointPositions(model.skeleton, {});
    p[Dof(kRoot, 3)] = centre.x() - rest[kRoot].x();
    p[Dof(kRoot, 5)] = centre.z() - rest[kRoot].z();
    p[Dof(kRoot, 1)] = yaw;
    p[Dof(kLeftShoulder, 2)] = -1.25;
    p[Dof(kRightShoulder, 2)] = 1.25;
    p[Dof(kLeftElbow, 1)] = -0.2;
    p[Dof(kRightElbow, 1)] = 0.2;
    return p;
  }

  // Fits stature, overall girth, arm and leg length to the silhouettes of the
  // current frame with the pose held; lengths scale whole limbs symmetrically.
  void FitSize(std::vector<double>* dofs) {
    const std::vector<Vector3d> before = JointPositions(model.skeleton, *dofs);
    Eigen::VectorXd x(4), step(4), vlo(4), vhi(4);
    x << shape.stature, shape.girth[kSegChest], shape.length[kSegLeftUpperArm],
        shape.length[kSegLeftThigh];
    step << 0.03, 0.06, 0.05, 0.05;
    vlo << 0.6, 0.7, 0.8, 0.8;
    vhi << 1.3, 1.5, 1.25, 1.25;
    auto apply = [&](const Eigen::VectorXd& v) {
      shape.stature = v[0];
      shape.girth.fill(v[1]);
      for (int s : {kSegLeftUpperArm, kSegLeftForearm, kSegRightUpperArm, kSegRightForearm})
        shape.length[s] = v[2];
      for (int s : {kSegLeftThigh, kSegLeftShank, kSegRightThigh, kSegRightShank})
        shape.length[s] = v[3];
      BuildModel();
    };
    std::vector<double> trial = *dofs;
    auto f = [&](const Eigen::VectorXd& v) {
      apply(v);
      // Keep the feet where they were: the root height follows the stature.
      trial = *dofs;
      const std::vector<Vector3d> now = JointPositions(model.skeleton, trial);
      trial[Dof(kRoot, 4)] += before[kLeftAnkle].y() - now[kLeftAnkle].y();
      PrepareStage(stages[0], trial, 0);
      return Evaluate(stages[0], trial, 0);
    };
    PowellOptions po;
    po.max_evaluations = 60;
    po.max_iterations = 2;
    MinimisePowell(f, &x, step, vlo, vhi, po);
    f(x);  // leave the model built for the best shape
    *dofs = trial;
  }

  // The heading search: the torso stage from eight headings with the limbs
  // neutral. Returns the starting poses sorted by their fit.
  std::vector<std::vector<double>> Headings(const Vector3d& centre, const Stage& stage) {
    std::vector<std::pair<double, std::vector<double>>> starts;
    for (int k = 0; k < 8; ++k) {
      std::vector<double> p = NeutralPose(centre, 2 * kPi * k / 8 - kPi);
      const double v = FitStage(stage, &p, 0, 1.0);
      starts.push_back({v, p});
    }
    std::sort(starts.begin(), starts.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<std::vector<double>> out;
    for (auto& st : starts) out.push_back(std::move(st.second));
    return out;
  }

  // The best heading turned by `turn` radians, the torso refitted.
  std::vector<double> Turned(const Vector3d& centre, const std::vector<double>& from, double turn,
                             const Stage& stage) {
    const double yaw = from[Dof(kRoot, 1)] + turn;
    std::vector<double> p = NeutralPose(centre, std::atan2(std::sin(yaw), std::cos(yaw)));
    FitStage(stage, &p, 0, 1.0);
    return p;
  }

  // Initialisation with the generic body's proportions, scaled: stature from
  // the measured height, then stature, girth, arm and leg length with the
  // pose. The best heading and its opposite are fitted completely:
  // silhouettes barely tell front from back until the limbs are fitted
  // (knees and elbows bend one way only).
  std::vector<double> InitialiseScaled(const Vector3d& centre, BodyShape* fitted) {
    const BodyShape first_guess = InitialShape();
    shape = first_guess;
    BuildModel();
    std::vector<std::vector<double>> starts = Headings(centre, stages[0]);
    starts[1] = Turned(centre, starts[0], kPi, stages[0]);
    double best_value = 1e300;
    std::vector<double> best;
    for (int k = 0; k < 2; ++k) {
      std::vector<double> p = starts[k];
      FitAll(&p, 1.0, Grid::kWide);
      if (options.adapt_shape) {
        FitSize(&p);
        FitAll(&p, 0.5, Grid::kNarrow);
      }
      PrepareStage(stages[0], p, 1);
      const double v = Evaluate(stages[0], p, 1);
      if (v < best_value) best_value = v, best = p;
      if (options.adapt_shape && k == 0) {
        // The second heading starts from the same shape estimate as the first.
        shape = first_guess;
        BuildModel();
      }
    }
    if (options.adapt_shape) {
      // Refit the shape for the chosen heading.
      FitSize(&best);
      FitAll(&best, 0.35, Grid::kNone);
    }
    *fitted = shape;
    return best;
  }

  // Initialisation with proportions of the actor's own (ShapeParam), the
  // overall size held to the measured height and the lower foot on the floor.
  // The best heading and its opposite each get their own build: first the
  // trunk's proportions with the limbs neutral, then the limbs, then every
  // proportion with the limbs placed; the chosen one is refined at half
  // resolution.
  std::vector<double> InitialiseProportions(const Vector3d& centre, BodyShape* fitted) {
    const BodyShape first_guess = InitialShape();
    shape = first_guess;
    BuildModel();
    // The heading comes from the trunk alone: neutral limbs would turn the
    // body to cover arms swinging to the front and back with arms held out
    // to the sides.
    std::vector<std::vector<double>> starts = Headings(centre, trunk);
    starts[1] = Turned(centre, starts[0], kPi, trunk);
    double best_value = 1e300;
    std::vector<double> best;
    BodyShape best_shape = first_guess;
    for (int k = 0; k < 2; ++k) {
      std::vector<double> p = starts[k];
      shape = first_guess;
      BuildModel();
      FitShape(&p, kTrunkShape, 0, 240);
      FitStage(stages[0], &p, 0, 0.5);
      FitAll(&p, 1.0, Grid::kWide);
      FitShape(&p, kWholeShape, 0, 480);
      FitAll(&p, 0.5, Grid::kNarrow);
      PrepareStage(stages[0], p, 1);
      const double v = Evaluate(stages[0], p, 1);
      if (v < best_value) best_value = v, best = p, best_shape = shape;
    }
    shape = best_shape;
    BuildModel();
    FitShape(&best, kWholeShape, 1, 400);
    FitAll(&best, 0.35, Grid::kNone);
    *fitted = shape;
    return best;
  }

  BodyShape InitialShape() const {
    BodyShape s;
    if (options.adapt_shape) s.stature = std::clamp(actor_height / 1.75, 0.6, 1.3);
    return s;
  }

  // The body proportions the tracker adapts beyond stature (which follows the
  // measured height). Each scales a group of segments symmetrically; lengths scale along a
  // segment's axis, girths across it (the chest's and pelvis's girth also set shoulder and hip
  // width). kNeckRatio is BodyShape::neck_ratio: a large head on a thin neck.
  enum ShapeParam {
    kHeadLength,
    kHeadGirth,
    kTorsoLength,
    kTorsoGirth,
    kArmLength,
    kArmGirth,
    kLegLength,
    kLegGirth,
    kNeckRatio,
    kShapeParamCount
  };
  struct ShapeParamSpec {
    bool length;  // scales lengths (else girths) of its segments
    std::vector<int> segments;
    double step, lo, hi;
  };
  static const ShapeParamSpec& ShapeSpec(int param) {
    static const ShapeParamSpec k[kShapeParamCount] = {
        {true, {kSegHead}, 0.08, 0.7, kMaxHeadScale},
        {false, {kSegHead}, 0.1, 0.7, kMaxHeadScale},
        {true, {kSegPelvis, kSegAbdomen, kSegChest}, 0.05, 0.7, 1.4},
        {false, {kSegPelvis, kSegAbdomen, kSegChest}, 0.06, 0.6, 1.5},
        {true,
         {kSegLeftUpperArm, kSegLeftForearm, kSegRightUpperArm, kSegRightForearm},
         0.05,
         0.7,
         1.4},
        {false,
         {kSegLeftUpperArm, kSegLeftForearm, kSegLeftHand, kSegRightUpperArm, kSegRightForearm,
          kSegRightHand},
         0.08,
         0.55,
         1.6},
        {true, {kSegLeftThigh, kSegLeftShank, kSegRightThigh, kSegRightShank}, 0.05, 0.6, 1.4},
        {false,
         {kSegLeftThigh, kSegLeftShank, kSegLeftFoot, kSegRightThigh, kSegRightShank,
          kSegRightFoot},
         0.08,
         0.55,
         1.6},
        {false, {}, 0.1, kMinNeckRatio, 1.0}};  // kNeckRatio: no segment of its own
    return k[param];
  }
  // The parameters an actor's build is fitted with before its limbs are
  // placed: what the torso stage sees with the limbs in their neutral pose.
  static constexpr uint32_t kTrunkShape = 1u << kHeadLength | 1u << kHeadGirth |
                                          1u << kTorsoLength | 1u << kTorsoGirth | 1u << kNeckRatio;
  // Every proportion; the overall size follows the measured height.
  static constexpr uint32_t kWholeShape = (1u << kShapeParamCount) - 1;

  double ShapeValue(int param) const {
    if (param == kNeckRatio) return shape.neck_ratio;
    const ShapeParamSpec& sp = ShapeSpec(param);
    return sp.length ? shape.length[sp.segments[0]] : shape.girth[sp.segments[0]];
  }

  void SetShapeValue(int param, double v) {
    if (param == kNeckRatio) shape.neck_ratio = v;
    const ShapeParamSpec& sp = ShapeSpec(param);
    for (int s : sp.segments) (sp.length ? shape.length[s] : shape.girth[s]) = v;
  }

  // The lowest and highest points of the model standing in the rest pose.
  std::pair<double, double> RestExtent() const {
    double bottom = 1e30, top = -1e30;
    for (const auto& p : model.mesh.positions) {
      bottom = std::min(bottom, double(p[1]));
      top = std::max(top, double(p[1]));
    }
    return {bottom, top};
  }

  // Fits the proportions in `params` (bits of ShapeParam) to the silhouettes
  // of the current frame with the pose held: the whole body's XOR at `level`.
  // Real actors differ from the generic body in more than size (a large head
  // fitted with a small one pulls the arms up to cover it), so head, torso,
  // arms and legs each have a length and a girth of their own.
  void FitShape(std::vector<double>* dofs, uint32_t params, int level, int budget) {
    std::vector<int> which;
    for (int k = 0; k < kShapeParamCount; ++k) {
      if (params >> k & 1) which.push_back(k);
    }
    const int n = int(which.size());
    Eigen::VectorXd x(n), step(n), vlo(n), vhi(n);
    for (int i = 0; i < n; ++i) {
      const ShapeParamSpec& sp = ShapeSpec(which[i]);
      x[i] = std::clamp(ShapeValue(which[i]), sp.lo, sp.hi);
      step[i] = sp.step, vlo[i] = sp.lo, vhi[i] = sp.hi;
    }
    std::vector<double> trial = *dofs;
    // The lower foot stands on the floor (y = 0): the root height follows
    // the legs, and a long trunk cannot pass for long legs.
    auto stand = [&] {
      const double ankle_above_sole =
          JointPositions(model.skeleton, {})[kLeftAnkle].y() - RestExtent().first;
      trial = *dofs;
      const std::vector<Vector3d> now = JointPositions(model.skeleton, trial);
      trial[Dof(kRoot, 4)] +=
          ankle_above_sole - std::min(now[kLeftAnkle].y(), now[kRightAnkle].y());
    };
    auto f = [&](const Eigen::VectorXd& v) {
      for (int i = 0; i < n; ++i) SetShapeValue(which[i], v[i]);
      BuildModel();
      stand();
      if (actor_height > 0) {
        // The actor's measured height fixes the overall size: proportions
        // trade against each other (a larger head, a shorter trunk). It is
        // the posed model's height that must match: a walking actor stands
        // lower than in the rest pose, and a model scaled to its rest height
        // would leave the top of the head uncovered. Heights scale with
        // stature (the feet stay on the floor), so one step matches them.
        std::vector<uint32_t> all(model.mesh.positions.size());
        std::iota(all.begin(), all.end(), 0u);
        std::vector<Vector3f> posed;
        SkinVertices(all, Skinning(trial), &posed);
        double top = -1e30;
        for (const Vector3f& p : posed) top = std::max(top, double(p.y()));
        shape.stature = std::clamp(shape.stature * actor_height / top, 0.5, 1.4);
        BuildModel();
        stand();
      }
      PrepareStage(stages[0], trial, level);
      return Evaluate(stages[0], trial, level);
    };
    PowellOptions po;
    po.max_evaluations = budget;
    po.max_iterations = 6;
    MinimisePowell(f, &x, step, vlo, vhi, po);
    f(x);  // leave the model built for the best shape
    *dofs = trial;
  }

  // The arms' length over the kept frames. One frame's arms, hanging in front
  // of the trunk in most views, barely show their length: CesiumMan's first
  // frame fits them 0.93 times the generic body's where its swinging arms say
  // 1.2. Alternates the length (poses held) with the arms' poses of each kept
  // frame. Arms do not change the actor's height, so nothing else moves.
  void RefitArmLength() {
    const std::vector<double> saved_prediction = std::move(prediction);
    prediction.clear();
    const ShapeParamSpec& sp = ShapeSpec(kArmLength);
    Eigen::VectorXd x(1), step(1), vlo(1), vhi(1);
    x[0] = ShapeValue(kArmLength), step[0] = sp.step, vlo[0] = sp.lo, vhi[0] = sp.hi;
    // Runs `fit` on every kept frame with that frame's silhouettes in place.
    auto for_each_kept = [&](const std::function<void(KeptFrame&)>& fit) {
      for (KeptFrame& k : kept) {
        std::swap(views, k.views);
        SetCollisionWeight();
        fit(k);
        std::swap(views, k.views);
      }
    };
    auto f = [&](const Eigen::VectorXd& v) {
      SetShapeValue(kArmLength, v[0]);
      BuildModel();
      double total = 0;
      for_each_kept([&](KeptFrame& k) {
        PrepareStage(stages[0], k.dofs, 1);
        total += Evaluate(stages[0], k.dofs, 1);
      });
      return total;
    };
    PowellOptions po;
    po.max_evaluations = 24;
    po.max_iterations = 2;
    // The length and the poses pull each other along (poses fitted to short
    // arms hold them short): rounds until the length settles.
    for (int round = 0; round < 6; ++round) {
      const double before = x[0];
      MinimisePowell(f, &x, step, vlo, vhi, po);
      f(x);
      if (round > 0 && std::abs(x[0] - before) < 0.01) break;
      for_each_kept([&](KeptFrame& k) {
        for (size_t st : {size_t{1}, size_t{2}}) FitStage(stages[st], &k.dofs, 1, 0.35);
      });
    }
    prediction = saved_prediction;
  }
};

Tracker::Tracker(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Tracker::~Tracker() = default;

StatusOr<std::unique_ptr<Tracker>> Tracker::Create(std::vector<Camera> cameras,
                                                   const TrackerOptions& options) {
  if (cameras.empty()) return InvalidArgument("tracker: no cameras");
  for (const Camera& c : cameras) {
    FVV_RETURN_IF_ERROR(ValidateCalibration(c, "tracker: camera \"" + c.name + "\""));
    if (c.width < 16 || c.height < 16) return InvalidArgument("tracker: camera images under 16x16");
  }
  auto impl = std::make_unique<Impl>(options);
  impl->cameras = std::move(cameras);
  impl->BuildModel();
  return std::unique_ptr<Tracker>(new Tracker(std::move(impl)));
}

StatusOr<FrameFit> Tracker::Initialise(const std::vector<Image>& silhouettes) {
  Impl& m = *impl_;
  int usable = 0;
  FVV_RETURN_IF_ERROR(m.SetSilhouettes(silhouettes, &usable));
  if (usable < 2) {
    return InvalidArgument("tracker: initialisation needs the actor in at least 2 cameras, found " +
                           std::to_string(usable));
  }
  m.SetCollisionWeight();
  m.evaluations = 0;
  Vector3d centre;
  double height = 1.75;
  if (!m.Locate(silhouettes, &centre, &height))
    return InvalidArgument("tracker: cannot locate the actor");
  m.actor_height = height;
  // The generic body's proportions at the actor's size first. An actor they
  // do not fit (a cartoon character's large head and short legs) is fitted
  // again with proportions of its own, and the better fit kept.
  BodyShape shape;
  std::vector<double> best = m.InitialiseScaled(centre, &shape);
  if (m.options.adapt_shape) {
    m.PrepareStage(m.stages[0], best, 1);
    const double scaled = m.Evaluate(m.stages[0], best, 1);
    FrameFit scaled_fit;
    m.Measure(best, &scaled_fit);
    if (scaled_fit.iou < m.options.proportions_iou) {
      BodyShape own;
      std::vector<double> p = m.InitialiseProportions(centre, &own);
      m.PrepareStage(m.stages[0], p, 1);
      if (m.Evaluate(m.stages[0], p, 1) < scaled) {
        best = p, shape = own;
        m.own_proportions = m.options.arm_refit_frames > 0;
      }
    }
  }
  m.shape = shape;
  m.BuildModel();
  m.TryLegsExchanged(&best);
  FrameFit fit;
  m.Measure(best, &fit);
  fit.evaluations = m.evaluations;
  m.last = m.previous = best;
  m.initialised = true;
  return fit;
}

StatusOr<FrameFit> Tracker::Track(const std::vector<Image>& silhouettes) {
  Impl& m = *impl_;
  if (!m.initialised) return Initialise(silhouettes);
  int usable = 0;
  FVV_RETURN_IF_ERROR(m.SetSilhouettes(silhouettes, &usable));
  m.evaluations = 0;
  // Damped constant-velocity prediction.
  std::vector<double> p = m.last;
  for (size_t d = 0; d < p.size(); ++d) {
    p[d] = std::clamp(m.last[d] + 0.6 * (m.last[d] - m.previous[d]), m.lo[d], m.hi[d]);
  }
  m.prediction = p;
  FrameFit fit;
  if (usable == 0) {
    fit.dofs = p;
    fit.poor = true;
    fit.note = "no silhouette in any camera: pose predicted";
  } else {
    m.SetCollisionWeight();
    m.FitAll(&p, 0.5, Impl::Grid::kNarrow);
    m.Measure(p, &fit);
    if (fit.iou < m.options.retry_iou) m.Recover(&p, &fit);
    if (usable < 2) {
      fit.poor = true;
      fit.note = "actor seen by " + std::to_string(usable) + " camera only";
    }
  }
  m.prediction.clear();
  ++m.frames_tracked;
  // Poorly fitting frames are kept too: an actor built unlike the generic
  // body fits poorly until its proportions are right.
  if (m.own_proportions && !m.arms_refitted && usable >= 2 &&
      m.frames_tracked % std::max(1, m.options.arm_refit_spacing) == 0) {
    m.kept.push_back({m.views, fit.dofs});
    if (int(m.kept.size()) >= m.options.arm_refit_frames) {
      m.RefitArmLength();
      m.arms_refitted = true;
      m.kept.clear();
      m.SetCollisionWeight();  // the current frame's views are in place again
      // This frame's pose with the new arms.
      m.prediction = p;
      m.FitAll(&fit.dofs, 0.35, Impl::Grid::kNone);
      m.prediction.clear();
      m.Measure(fit.dofs, &fit);
    }
  }
  fit.evaluations = m.evaluations;
  m.previous = m.last;
  m.last = fit.dofs;
  return fit;
}

Image Tracker::ModelSilhouette(uint32_t camera, const std::vector<double>& dofs) const {
  const Impl& m = *impl_;
  const Camera& cam = m.cameras.at(camera);
  View v;
  v.w = int(cam.width), v.h = int(cam.height);
  v.r = CameraRotation(cam).cast<float>();
  v.t = CameraTranslation(cam).cast<float>();
  v.fx = float(cam.fx), v.fy = float(cam.fy), v.cx = float(cam.cx), v.cy = float(cam.cy);
  for (int i = 0; i < 5; ++i) v.k[i] = float(cam.distortion[i]);
  v.distorted = std::any_of(v.k.begin(), v.k.end(), [](float x) { return x != 0; });
  std::vector<uint32_t> all(m.model.mesh.positions.size());
  std::iota(all.begin(), all.end(), 0u);
  std::vector<Vector3f> posed;
  m.SkinVertices(all, m.Skinning(dofs), &posed);
  std::vector<Vector2f> px(posed.size());
  for (size_t i = 0; i < posed.size(); ++i) px[i] = v.Project(posed[i]);
  std::vector<uint32_t> tris;
  for (const auto& t : m.model.mesh.triangles) tris.insert(tris.end(), t.begin(), t.end());
  Image out;
  out.width = cam.width, out.height = cam.height, out.channels = 1;
  out.pixels.assign(size_t{cam.width} * cam.height, 0);
  RasterBox box{v.w, v.h, -1, -1};
  RasteriseSilhouette(tris, px, v.w, v.h, out.pixels.data(), &box);
  for (uint8_t& p : out.pixels) p = p ? 255 : 0;
  return out;
}

const BodyShape& Tracker::shape() const { return impl_->shape; }

BodyModel Tracker::Model() const { return MakeGenericBody(impl_->shape); }

}  // namespace fvv
