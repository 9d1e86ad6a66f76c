#include "encoder/track/tracker.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "encoder/body/kinematics.h"
#include "encoder/capture/calibration.h"
#include "encoder/track/body_initialiser.h"
#include "encoder/track/pose_fitter.h"
#include "encoder/track/silhouette_raster.h"

namespace fvv {
namespace {

// The actor's height in pixels: the tallest silhouette's extent.
int ActorPixels(const std::vector<Image>& silhouettes) {
  int tallest = 0;
  for (const Image& s : silhouettes) {
    int top = -1, bottom = -1;
    for (uint32_t y = 0; y < s.height; ++y) {
      const uint8_t* row = &s.pixels[size_t(y) * s.width];
      if (std::any_of(row, row + s.width, [](uint8_t p) { return p != 0; })) {
        if (top < 0) top = int(y);
        bottom = int(y);
      }
    }
    if (top >= 0) tallest = std::max(tallest, bottom - top + 1);
  }
  return tallest;
}

}  // namespace

struct Tracker::Impl {
  explicit Impl(std::vector<Camera> cameras, const TrackerOptions& o)
      : fitter(std::move(cameras), o), initialiser(&fitter) {}

  PoseFitter fitter;
  BodyInitialiser initialiser;
  std::vector<double> last, previous;
  bool initialised = false;
  // An actor fitted with proportions of its own has its arms' length fitted
  // again over several frames once tracking has moved them.
  std::vector<BodyInitialiser::KeptFrame> kept;
  int frames_tracked = 0;
  bool arms_refitted = false;

  // A poor fit, or joints off the sightings: the limbs searched again.
  bool NeedsRecovery(const FrameFit& fit) const {
    return fit.iou < fitter.options.retry_iou ||
           fit.keypoint_distance > fitter.options.keypoint_disagreement;
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
  TrackerOptions o = options;
  if (o.fixed_shape) o.adapt_shape = true;  // the search that fits it, then the fixed shape
  return std::unique_ptr<Tracker>(new Tracker(std::make_unique<Impl>(std::move(cameras), o)));
}

StatusOr<FrameFit> Tracker::Initialise(const std::vector<Image>& silhouettes,
                                       const std::vector<std::vector<JointSighting>>& sightings) {
  PoseFitter& f = impl_->fitter;
  // The working resolution from the actor's size: enough pixels across the
  // body for the XOR to place a limb, no more.
  if (silhouettes.size() == f.cameras.size()) {
    const int target = std::max(16, f.options.fine_height);
    f.fine_factor = std::max(2, ActorPixels(silhouettes) / target);
  }
  int usable = 0;
  FVV_RETURN_IF_ERROR(f.SetFrame(silhouettes, sightings, &usable));
  if (usable < 2) {
    return InvalidArgument("tracker: initialisation needs the actor in at least 2 cameras, found " +
                           std::to_string(usable));
  }
  f.SetWeights();
  f.evaluations = 0;
  StatusOr<std::vector<double>> best = impl_->initialiser.Initialise(silhouettes);
  if (!best.ok()) return best.status();
  FrameFit fit;
  f.Measure(*best, &fit);
  if (fit.keypoint_distance > f.options.keypoint_disagreement) f.Recover(&*best, &fit);
  fit.evaluations = f.evaluations;
  impl_->last = impl_->previous = *best;
  impl_->initialised = true;
  return fit;
}

Status Tracker::Resume(const std::vector<double>& previous, const std::vector<double>& last,
                       const std::vector<Image>& silhouettes) {
  PoseFitter& f = impl_->fitter;
  if (!f.options.fixed_shape) return InvalidArgument("tracker: resuming needs the actor's shape");
  const size_t n = f.model.skeleton.Dofs().size();
  if (previous.size() != n || last.size() != n) {
    return InvalidArgument("tracker: resuming from poses of " + std::to_string(last.size()) +
                           " DOFs, the body has " + std::to_string(n));
  }
  if (silhouettes.size() == f.cameras.size()) {
    const int target = std::max(16, f.options.fine_height);
    f.fine_factor = std::max(2, ActorPixels(silhouettes) / target);
  }
  f.shape = *f.options.fixed_shape;
  f.BuildModel();
  impl_->previous = previous;
  impl_->last = last;
  impl_->initialised = true;
  return Status::Ok();
}

StatusOr<FrameFit> Tracker::Track(const std::vector<Image>& silhouettes,
                                  const std::vector<std::vector<JointSighting>>& sightings) {
  Impl& m = *impl_;
  PoseFitter& f = m.fitter;
  if (!m.initialised) return Initialise(silhouettes, sightings);
  int usable = 0;
  FVV_RETURN_IF_ERROR(f.SetFrame(silhouettes, sightings, &usable));
  f.evaluations = 0;
  // Damped constant-velocity prediction.
  std::vector<double> p = m.last;
  for (size_t d = 0; d < p.size(); ++d) {
    p[d] = std::clamp(m.last[d] + 0.6 * (m.last[d] - m.previous[d]), f.lo[d], f.hi[d]);
  }
  f.prediction = p;
  FrameFit fit;
  if (usable == 0) {
    fit.dofs = p;
    fit.poor = true;
    fit.note = "no silhouette in any camera: pose predicted";
  } else {
    f.SetWeights();
    f.FitAll(&p, 0.5, Grid::kNarrow);
    f.Measure(p, &fit);
    if (m.NeedsRecovery(fit)) f.Recover(&p, &fit);
    if (usable < 2) {
      fit.poor = true;
      fit.note = "actor seen by " + std::to_string(usable) + " camera only";
    }
  }
  f.prediction.clear();
  ++m.frames_tracked;
  // Poorly fitting frames are kept too: an actor built unlike the generic
  // body fits poorly until its proportions are right.
  if (m.initialiser.own_proportions() && f.options.arm_refit_frames > 0 && !m.arms_refitted &&
      usable >= 2 && m.frames_tracked % std::max(1, f.options.arm_refit_spacing) == 0) {
    m.kept.push_back({f.CopyFrame(), fit.dofs});
    if (int(m.kept.size()) >= f.options.arm_refit_frames) {
      m.initialiser.RefitArmLength(&m.kept);
      m.arms_refitted = true;
      m.kept.clear();
      f.SetWeights();  // the current frame's views are in place again
      // This frame's pose with the new arms.
      f.prediction = p;
      f.FitAll(&fit.dofs, 0.35, Grid::kNone);
      f.prediction.clear();
      f.Measure(fit.dofs, &fit);
    }
  }
  fit.evaluations = f.evaluations;
  m.previous = m.last;
  m.last = fit.dofs;
  return fit;
}

Image Tracker::ModelSilhouette(uint32_t camera, const std::vector<double>& dofs) const {
  const PoseFitter& f = impl_->fitter;
  return BodySilhouette(f.model, f.cameras.at(camera), dofs);
}

const BodyShape& Tracker::shape() const { return impl_->fitter.shape; }

BodyModel Tracker::Model() const { return MakeGenericBody(impl_->fitter.shape); }

Image BodySilhouette(const BodyModel& model, const Camera& camera,
                     const std::vector<double>& dofs) {
  FitView v;
  v.SetCamera(camera, 1);
  const std::vector<Eigen::Vector3f> posed =
      SkinPositions(model.mesh, SkinningMatrices(model.skeleton, dofs));
  std::vector<Eigen::Vector2f> px(posed.size());
  for (size_t i = 0; i < posed.size(); ++i) px[i] = v.Project(posed[i]);
  std::vector<uint32_t> tris;
  for (const auto& t : model.mesh.triangles) tris.insert(tris.end(), t.begin(), t.end());
  Image out;
  out.width = camera.width, out.height = camera.height, out.channels = 1;
  out.pixels.assign(size_t{camera.width} * camera.height, 0);
  RasterBox box{v.w, v.h, -1, -1};
  RasteriseSilhouette(tris, px, v.w, v.h, out.pixels.data(), &box);
  for (uint8_t& p : out.pixels) p = p ? 255 : 0;
  return out;
}

}  // namespace fvv
