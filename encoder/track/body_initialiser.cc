#include "encoder/track/body_initialiser.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <numeric>
#include <string>

#include "encoder/body/kinematics.h"
#include "encoder/capture/calibration.h"
#include "encoder/track/feature_registration.h"
#include "encoder/track/features.h"
#include "encoder/track/powell.h"

namespace fvv {
namespace {

using Eigen::Vector3d;
using Eigen::Vector3f;

constexpr double kPi = 3.14159265358979323846;

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
const ShapeParamSpec& ShapeSpec(int param) {
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
       {kSegLeftThigh, kSegLeftShank, kSegLeftFoot, kSegRightThigh, kSegRightShank, kSegRightFoot},
       0.08,
       0.55,
       1.6},
      {false, {}, 0.1, kMinNeckRatio, 1.0}};  // kNeckRatio: no segment of its own
  return k[param];
}
// The parameters an actor's build is fitted with before its limbs are
// placed: what the torso stage sees with the limbs in their neutral pose.
constexpr uint32_t kTrunkShape = 1u << kHeadLength | 1u << kHeadGirth | 1u << kTorsoLength |
                                 1u << kTorsoGirth | 1u << kNeckRatio;
// Every proportion; the overall size follows the measured height.
constexpr uint32_t kWholeShape = (1u << kShapeParamCount) - 1;

}  // namespace

// A rough global position and height from the silhouettes' geometry: the
// point nearest all rays through the silhouette centroids, and the top of
// the silhouettes above it.
bool BodyInitialiser::Locate(const std::vector<Image>& sils, Vector3d* centre, double* height) {
  Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
  Vector3d b = Vector3d::Zero();
  int rays = 0;
  std::vector<std::pair<const Camera*, Eigen::Vector2d>> tops;
  for (size_t c = 0; c < fit_.cameras.size(); ++c) {
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
    const Vector3d o = CameraCentre(fit_.cameras[c]);
    const Vector3d d = (UnprojectPixel(fit_.cameras[c], {sx / n, sy / n}, 1.0) - o).normalized();
    const Eigen::Matrix3d p = Eigen::Matrix3d::Identity() - d * d.transpose();
    a += p, b += p * o, ++rays;
    tops.push_back({&fit_.cameras[c], Eigen::Vector2d(top_x, top)});
  }
  if (rays < 2) return false;
  *centre = a.ldlt().solve(b);
  std::vector<double> heights;
  for (const auto& [cam, px] : tops) {
    // The top pixel's ray, at the depth of the vertical through the centre.
    const Vector3d o = CameraCentre(*cam);
    const Vector3d d = (UnprojectPixel(*cam, px, 1.0) - o).normalized();
    const Eigen::Vector2d flat(d.x(), d.z());
    const double along = flat.squaredNorm() > 1e-9
                             ? Eigen::Vector2d(centre->x() - o.x(), centre->z() - o.z()).dot(flat) /
                                   flat.squaredNorm()
                             : 0;
    heights.push_back(o.y() + along * d.y());
  }
  std::nth_element(heights.begin(), heights.begin() + heights.size() / 2, heights.end());
  *height = heights[heights.size() / 2];
  return true;
}

std::vector<double> BodyInitialiser::NeutralPose(const Vector3d& centre, double yaw) const {
  std::vector<double> p(fit_.refs.size(), 0.0);
  const std::vector<Vector3d> rest = JointPositions(fit_.model.skeleton, {});
  p[fit_.Dof(kRoot, 3)] = centre.x() - rest[kRoot].x();
  p[fit_.Dof(kRoot, 5)] = centre.z() - rest[kRoot].z();
  p[fit_.Dof(kRoot, 1)] = yaw;
  p[fit_.Dof(kLeftShoulder, 2)] = -1.25;
  p[fit_.Dof(kRightShoulder, 2)] = 1.25;
  p[fit_.Dof(kLeftElbow, 1)] = -0.2;
  p[fit_.Dof(kRightElbow, 1)] = 0.2;
  return p;
}

// Fits stature, overall girth, arm and leg length to the silhouettes of the
// current frame with the pose held; lengths scale whole limbs symmetrically.
void BodyInitialiser::FitSize(std::vector<double>* dofs) {
  const std::vector<Vector3d> before = JointPositions(fit_.model.skeleton, *dofs);
  Eigen::VectorXd x(4), step(4), vlo(4), vhi(4);
  x << fit_.shape.stature, fit_.shape.girth[kSegChest], fit_.shape.length[kSegLeftUpperArm],
      fit_.shape.length[kSegLeftThigh];
  step << 0.03, 0.06, 0.05, 0.05;
  vlo << 0.6, 0.7, 0.8, 0.8;
  vhi << 1.3, 1.5, 1.25, 1.25;
  auto apply = [&](const Eigen::VectorXd& v) {
    fit_.shape.stature = v[0];
    fit_.shape.girth.fill(v[1]);
    for (int s : {kSegLeftUpperArm, kSegLeftForearm, kSegRightUpperArm, kSegRightForearm})
      fit_.shape.length[s] = v[2];
    for (int s : {kSegLeftThigh, kSegLeftShank, kSegRightThigh, kSegRightShank})
      fit_.shape.length[s] = v[3];
    fit_.BuildModel();
  };
  std::vector<double> trial = *dofs;
  auto f = [&](const Eigen::VectorXd& v) {
    apply(v);
    // Keep the feet where they were: the root height follows the stature.
    trial = *dofs;
    const std::vector<Vector3d> now = JointPositions(fit_.model.skeleton, trial);
    trial[fit_.Dof(kRoot, 4)] += before[kLeftAnkle].y() - now[kLeftAnkle].y();
    fit_.PrepareStage(fit_.stages[kTorsoStage], trial, 0);
    return fit_.Evaluate(fit_.stages[kTorsoStage], trial, 0);
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
std::vector<std::vector<double>> BodyInitialiser::Headings(const Vector3d& centre,
                                                           const PoseStage& stage) {
  std::vector<std::pair<double, std::vector<double>>> starts;
  for (int k = 0; k < 8; ++k) {
    std::vector<double> p = NeutralPose(centre, 2 * kPi * k / 8 - kPi);
    const double v = fit_.FitStage(stage, &p, 0, 1.0);
    starts.push_back({v, p});
  }
  std::sort(starts.begin(), starts.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<std::vector<double>> out;
  for (auto& st : starts) out.push_back(std::move(st.second));
  return out;
}

// The best heading turned by `turn` radians, the torso refitted.
std::vector<double> BodyInitialiser::Turned(const Vector3d& centre, const std::vector<double>& from,
                                            double turn, const PoseStage& stage) {
  const double yaw = from[fit_.Dof(kRoot, 1)] + turn;
  std::vector<double> p = NeutralPose(centre, std::atan2(std::sin(yaw), std::cos(yaw)));
  fit_.FitStage(stage, &p, 0, 1.0);
  return p;
}

// Where a first frame's fit starts: the heading search's best and its
// opposite, then the placed body where there is one (its limbs near: its
// searches are narrow); the objective, sightings included, decides.
std::vector<std::vector<double>> BodyInitialiser::Starts(const Vector3d& centre,
                                                         const PoseStage& stage,
                                                         const std::vector<double>* placed) {
  std::vector<std::vector<double>> starts = Headings(centre, stage);
  starts[1] = Turned(centre, starts[0], kPi, stage);
  starts.resize(2);
  if (placed) starts.push_back(*placed);
  return starts;
}

// Initialisation with the generic body's proportions, scaled: stature from
// the measured height, then stature, girth, arm and leg length with the
// pose. The best heading and its opposite are fitted completely:
// silhouettes barely tell front from back until the limbs are fitted
// (knees and elbows bend one way only).
std::vector<double> BodyInitialiser::InitialiseScaled(const Vector3d& centre,
                                                      const std::vector<double>* start,
                                                      BodyShape* fitted) {
  const BodyShape first_guess = InitialShape();
  fit_.shape = first_guess;
  fit_.BuildModel();
  const std::vector<std::vector<double>> starts = Starts(centre, fit_.stages[kTorsoStage], start);
  double best_value = 1e300;
  std::vector<double> best;
  for (size_t k = 0; k < starts.size(); ++k) {
    std::vector<double> p = starts[k];
    const bool placed = k == 2;
    fit_.FitAll(&p, placed ? 0.5 : 1.0, placed ? Grid::kNarrow : Grid::kWide);
    if (fit_.options.adapt_shape) {
      FitSize(&p);
      fit_.FitAll(&p, 0.5, Grid::kNarrow);
    }
    const double v = fit_.EvaluateBody(p);
    if (v < best_value) best_value = v, best = p;
    if (fit_.options.adapt_shape && k + 1 < starts.size()) {
      // The next start begins from the same shape estimate as the first.
      fit_.shape = first_guess;
      fit_.BuildModel();
    }
  }
  if (fit_.options.adapt_shape) {
    // Refit the shape for the chosen heading.
    FitSize(&best);
    fit_.FitAll(&best, 0.35, Grid::kNone);
  }
  *fitted = fit_.shape;
  return best;
}

// Initialisation with proportions of the actor's own (ShapeParam), the
// overall size held to the measured height and the lower foot on the floor.
// The best heading and its opposite each get their own build: first the
// trunk's proportions with the limbs neutral, then the limbs, then every
// proportion with the limbs placed; the chosen one is refined at half
// resolution.
std::vector<double> BodyInitialiser::InitialiseProportions(const Vector3d& centre,
                                                           const std::vector<double>* start,
                                                           BodyShape* fitted) {
  const BodyShape first_guess = InitialShape();
  fit_.shape = first_guess;
  fit_.BuildModel();
  // The heading comes from the trunk alone: neutral limbs would turn the
  // body to cover arms swinging to the front and back with arms held out
  // to the sides.
  const std::vector<std::vector<double>> starts = Starts(centre, fit_.trunk, start);
  double best_value = 1e300;
  std::vector<double> best;
  BodyShape best_shape = first_guess;
  for (size_t k = 0; k < starts.size(); ++k) {
    std::vector<double> p = starts[k];
    fit_.shape = first_guess;
    fit_.BuildModel();
    FitShape(&p, kTrunkShape, 0, 240);
    fit_.FitStage(fit_.stages[kTorsoStage], &p, 0, 0.5);
    const bool placed = k == 2;
    fit_.FitAll(&p, placed ? 0.5 : 1.0, placed ? Grid::kNarrow : Grid::kWide);
    FitShape(&p, kWholeShape, 0, 480);
    fit_.FitAll(&p, 0.5, Grid::kNarrow);
    const double v = fit_.EvaluateBody(p);
    if (v < best_value) best_value = v, best = p, best_shape = fit_.shape;
  }
  fit_.shape = best_shape;
  fit_.BuildModel();
  FitShape(&best, kWholeShape, 1, 400);
  fit_.FitAll(&best, 0.35, Grid::kNone);
  *fitted = fit_.shape;
  return best;
}

BodyShape BodyInitialiser::InitialShape() const {
  BodyShape s;
  if (fit_.options.adapt_shape) s.stature = std::clamp(actor_height_ / 1.75, 0.6, 1.3);
  return s;
}

double BodyInitialiser::ShapeValue(int param) const {
  if (param == kNeckRatio) return fit_.shape.neck_ratio;
  const ShapeParamSpec& sp = ShapeSpec(param);
  return sp.length ? fit_.shape.length[sp.segments[0]] : fit_.shape.girth[sp.segments[0]];
}

void BodyInitialiser::SetShapeValue(int param, double v) {
  if (param == kNeckRatio) fit_.shape.neck_ratio = v;
  const ShapeParamSpec& sp = ShapeSpec(param);
  for (int s : sp.segments) (sp.length ? fit_.shape.length[s] : fit_.shape.girth[s]) = v;
}

// The lowest and highest points of the model standing in the rest pose.
std::pair<double, double> BodyInitialiser::RestExtent() const {
  double bottom = 1e30, top = -1e30;
  for (const auto& p : fit_.model.mesh.positions) {
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
void BodyInitialiser::FitShape(std::vector<double>* dofs, uint32_t params, int level, int budget) {
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
        JointPositions(fit_.model.skeleton, {})[kLeftAnkle].y() - RestExtent().first;
    trial = *dofs;
    const std::vector<Vector3d> now = JointPositions(fit_.model.skeleton, trial);
    trial[fit_.Dof(kRoot, 4)] +=
        ankle_above_sole - std::min(now[kLeftAnkle].y(), now[kRightAnkle].y());
  };
  auto f = [&](const Eigen::VectorXd& v) {
    for (int i = 0; i < n; ++i) SetShapeValue(which[i], v[i]);
    fit_.BuildModel();
    stand();
    if (actor_height_ > 0) {
      // The actor's measured height fixes the overall size: proportions
      // trade against each other (a larger head, a shorter trunk). It is
      // the posed model's height that must match: a walking actor stands
      // lower than in the rest pose, and a model scaled to its rest height
      // would leave the top of the head uncovered. Heights scale with
      // stature (the feet stay on the floor), so one step matches them.
      std::vector<uint32_t> all(fit_.model.mesh.positions.size());
      std::iota(all.begin(), all.end(), 0u);
      std::vector<Vector3f> posed;
      fit_.SkinVertices(all, fit_.Skinning(trial), &posed);
      double top = -1e30;
      for (const Vector3f& p : posed) top = std::max(top, double(p.y()));
      fit_.shape.stature = std::clamp(fit_.shape.stature * actor_height_ / top, 0.5, 1.4);
      fit_.BuildModel();
      stand();
    }
    fit_.PrepareStage(fit_.stages[kTorsoStage], trial, level);
    return fit_.Evaluate(fit_.stages[kTorsoStage], trial, level);
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
void BodyInitialiser::RefitArmLength(std::vector<KeptFrame>* kept) {
  const std::vector<double> saved_prediction = std::move(fit_.prediction);
  fit_.prediction.clear();
  const ShapeParamSpec& sp = ShapeSpec(kArmLength);
  Eigen::VectorXd x(1), step(1), vlo(1), vhi(1);
  x[0] = ShapeValue(kArmLength), step[0] = sp.step, vlo[0] = sp.lo, vhi[0] = sp.hi;
  // Runs `fit` on every kept frame with that frame's silhouettes in place.
  auto for_each_kept = [&](const std::function<void(KeptFrame&)>& fit) {
    for (KeptFrame& k : *kept) {
      fit_.SwapFrame(&k.frame);
      fit_.SetWeights();
      fit(k);
      fit_.SwapFrame(&k.frame);
    }
  };
  auto f = [&](const Eigen::VectorXd& v) {
    SetShapeValue(kArmLength, v[0]);
    fit_.BuildModel();
    double total = 0;
    for_each_kept([&](KeptFrame& k) { total += fit_.EvaluateBody(k.dofs); });
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
      for (StageId st : {kLeftArmStage, kRightArmStage})
        fit_.FitStage(fit_.stages[st], &k.dofs, kFine, 0.35);
    });
  }
  fit_.prediction = saved_prediction;
}

StatusOr<std::vector<double>> BodyInitialiser::Initialise(const std::vector<Image>& silhouettes) {
  Vector3d centre;
  double height = 1.75;
  if (!Locate(silhouettes, &centre, &height))
    return InvalidArgument("tracker: cannot locate the actor");
  actor_height_ = height;
  BodyShape shape;
  std::vector<double> best, placed;
  const std::vector<double>* start = PlaceBySightings(&placed) ? &placed : nullptr;
  // The generic body's proportions at the actor's size first. An actor they
  // do not fit (a cartoon character's large head and short legs) is fitted
  // again with proportions of its own, and the better fit kept.
  best = InitialiseScaled(centre, start, &shape);
  if (fit_.options.adapt_shape) {
    const double scaled = fit_.EvaluateBody(best);
    FrameFit scaled_fit;
    fit_.Measure(best, &scaled_fit);
    if (scaled_fit.iou < fit_.options.proportions_iou) {
      BodyShape own;
      std::vector<double> p = InitialiseProportions(centre, start, &own);
      if (fit_.EvaluateBody(p) < scaled) {
        best = p, shape = own;
        own_proportions_ = true;
      }
    }
  }
  if (fit_.options.fixed_shape) {
    // A shape settled elsewhere: the heading and pose come from the same
    // search a run that fits the shape makes (with a shape held from the
    // start, silhouettes alone chose the back for the front on a walking
    // actor), then the pose is fitted again with the settled shape.
    shape = *fit_.options.fixed_shape;
    own_proportions_ = false;
    fit_.shape = shape;
    fit_.BuildModel();
    fit_.FitAll(&best, 0.35, Grid::kNarrow);
  }
  fit_.shape = shape;
  fit_.BuildModel();
  fit_.TryLegsExchanged(&best);
  return best;
}

bool BodyInitialiser::PlaceBySightings(std::vector<double>* dofs) {
  std::map<std::string, std::map<uint32_t, Eigen::Vector2d>> points;
  std::vector<double> sizes;
  for (size_t c = 0; c < fit_.joints.size(); ++c) {
    if (fit_.joints[c].empty()) continue;
    sizes.push_back(fit_.actor_px[c]);
    for (const JointSighting& j : fit_.joints[c]) {
      if (j.confidence >= 0.5) points[GenericJointName(j.joint)][uint32_t(c)] = j.pixel;
    }
  }
  if (sizes.size() < 2) return false;
  // Sightings are one or two hundredths of the actor's height off: a view
  // further off than that is a wrong one.
  std::nth_element(sizes.begin(), sizes.begin() + sizes.size() / 2, sizes.end());
  const double tolerance = 0.02 * sizes[sizes.size() / 2];
  const std::map<std::string, Feature3D> joints =
      TriangulateFeatures(points, fit_.cameras, tolerance);
  // The pose only: the build is the silhouettes' to fit (a few noisy
  // sightings make poor proportions).
  RegistrationOptions ro;
  ro.fit_shape = false;
  StatusOr<Registration> reg = RegisterSkeleton(joints, InitialShape(), {}, ro);
  if (!reg.ok()) return false;
  *dofs = reg->dofs;
  for (size_t d = 0; d < dofs->size(); ++d)
    (*dofs)[d] = std::clamp((*dofs)[d], fit_.lo[d], fit_.hi[d]);
  return true;
}

}  // namespace fvv
