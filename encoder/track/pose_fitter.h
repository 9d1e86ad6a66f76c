// The tracker's per-frame fit (internal to encoder/track): the objective, the
// XOR of the model's rendered silhouette with the image silhouettes summed
// over cameras, plus a keypoint term where 2D joint sightings are given and
// penalties on interpenetration and on leaving the predicted pose; and the
// hierarchical search over named stages of DOFs that minimises it.
//
// Stages run in the order of each part's effect on the silhouettes and its
// place in the kinematic chain: the torso (root and spine), each arm and leg
// (upper and lower parts jointly, after a small grid search over the upper
// joint to escape local minima), then hands, feet and head. Each runs Powell's
// method on a coarse level and then a fine one. Only what a stage moves is
// rasterised: the fixed parts are drawn once per stage and the XOR is counted
// inside the moving parts' bounding box (the rest comes from an integral
// image). Cameras are evaluated in parallel.
#ifndef FVV_ENCODER_TRACK_POSE_FITTER_H_
#define FVV_ENCODER_TRACK_POSE_FITTER_H_

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "codec/base/status.h"
#include "codec/base/thread_pool.h"
#include "container/cameras.h"
#include "encoder/body/generic_body.h"
#include "encoder/body/kinematics.h"
#include "encoder/io/image_io.h"
#include "encoder/track/tracker.h"

namespace fvv {

// One camera at one level: its scaled calibration, silhouette, the observed
// joints, and the per-stage raster of the parts that stay fixed.
struct FitView {
  int w = 0, h = 0;
  int factor = 1;  // full-resolution pixels per pixel of this level, each way
  Eigen::Matrix3f r;
  Eigen::Vector3f t;
  float fx = 0, fy = 0, cx = 0, cy = 0;
  std::array<float, 5> k{};
  bool distorted = false;
  std::vector<uint8_t> sil;  // 0/1
  int64_t sil_area = 0;
  std::vector<uint8_t> fixed, scratch;
  std::vector<Eigen::Vector2f> projected;  // per-evaluation vertex positions (no reallocations)
  std::vector<int32_t> xor_integral;       // (w + 1) x (h + 1) prefix sums of fixed ^ sil
  int64_t xor_total = 0;

  // Scaled from `camera` by `factor` (pixel centres kept).
  void SetCamera(const Camera& camera, int factor);
  Eigen::Vector2f Project(const Eigen::Vector3f& p) const;
  int64_t IntegralSum(int x0, int y0, int x1, int y1) const;  // inclusive box
};

// The stages, in the order they are fitted.
enum StageId : int {
  kTorsoStage,
  kLeftArmStage,
  kRightArmStage,
  kLeftLegStage,
  kRightLegStage,
  kHandsStage,
  kFeetStage,
  kHeadStage,
  kStageCount
};

// A set of DOFs optimised together, and what moves when they change.
struct PoseStage {
  std::string name;
  std::vector<int> dofs;               // indices into the DOF vector
  std::vector<uint32_t> moving_verts;  // vertices any moved bone influences
  std::vector<uint32_t> moving_tris, fixed_tris;
  int grid_dof_a = -1, grid_dof_b = -1, grid_dof_c = -1;  // grid search (indices into dofs)
  int twist = -1;  // the upper joint's twist: reset by a wide grid search
};

// How a stage's search starts: where it is (kNone), from a small grid around
// it (kNarrow, tracking), or from a wide grid of absolute angles (kWide).
enum class Grid { kNone, kNarrow, kWide };

// Levels of detail: silhouettes are fitted at a coarse level, then a fine one.
enum FitLevel : int { kCoarse = 0, kFine = 1 };

struct PoseFitter {
  PoseFitter(std::vector<Camera> cameras, const TrackerOptions& options);

  TrackerOptions options;
  std::vector<Camera> cameras;
  ThreadPool pool;
  BodyShape shape;
  BodyModel model;  // tracking resolution
  std::vector<DofRef> refs;
  std::vector<double> lo, hi;
  std::vector<PoseStage> stages;  // by StageId
  // The torso stage's DOFs with only the trunk drawn (pelvis to head): the
  // heading search at initialisation, which the limbs would mislead.
  PoseStage trunk;
  // Full-resolution pixels per fine-level pixel (the coarse level has twice
  // as many): chosen from the actor's size in the images at initialisation.
  int fine_factor = 2;
  // views[level][camera].
  std::vector<std::vector<FitView>> views;
  // The frame's joint sightings per camera (empty: none), and the actor's
  // height in each image (full-resolution pixels; 0: not seen).
  std::vector<std::vector<JointSighting>> joints;
  std::vector<double> actor_px;
  int evaluations = 0;
  double collision_weight = 0;  // pixels per metre of capsule overlap
  // A weak pull towards the predicted pose (pixels per squared radian) that
  // decides between poses whose silhouettes are nearly alike (a forearm
  // hidden in front of the torso); empty while initialising.
  std::vector<double> prediction;
  double smoothness_weight = 0;
  // Per camera and level: pixels of objective per unit of squared keypoint
  // error (the error in shares of the actor's height in that image).
  std::vector<double> keypoint_weight;

  int Dof(int bone, int kind) const { return DofIndex(model.skeleton, bone, kind); }

  // What SetFrame set, kept aside to fit a past frame again.
  struct Frame {
    std::vector<std::vector<FitView>> views;
    std::vector<std::vector<JointSighting>> joints;
    std::vector<double> actor_px;
  };
  Frame CopyFrame() const { return {views, joints, actor_px}; }
  void SwapFrame(Frame* frame) {
    std::swap(views, frame->views);
    std::swap(joints, frame->joints);
    std::swap(actor_px, frame->actor_px);
  }

  void BuildModel();
  // Takes the frame's silhouettes (and joint sightings, may be empty);
  // `usable`: cameras where the actor is seen.
  Status SetFrame(const std::vector<Image>& silhouettes,
                  const std::vector<std::vector<JointSighting>>& sightings, int* usable);
  std::vector<Eigen::Matrix4f> Skinning(const std::vector<double>& dofs) const;
  void SkinVertices(const std::vector<uint32_t>& verts, const std::vector<Eigen::Matrix4f>& skin,
                    std::vector<Eigen::Vector3f>* out) const;
  // Draws the fixed parts of `stage` at `dofs` into every view of `level`.
  void PrepareStage(const PoseStage& stage, const std::vector<double>& dofs, int level);
  // The objective at `level`, redrawing only `stage`'s moving parts (after
  // PrepareStage with the same fixed parts).
  double Evaluate(const PoseStage& stage, const std::vector<double>& dofs, int level);
  // The whole body's objective at the fine level.
  double EvaluateBody(const std::vector<double>& dofs);
  // Capsule overlap of forearms and hands with the torso, and of the legs
  // with each other, in metres (0 when nothing interpenetrates).
  double Overlap(const std::vector<double>& dofs) const;
  // The keypoint term at `level` (0 without sightings).
  double KeypointCost(const std::vector<double>& dofs, int level) const;
  // The weights of the penalties and the keypoint term, from the frame's
  // silhouette areas.
  void SetWeights();
  // Powell over one stage's DOFs, after an optional grid search.
  double FitStage(const PoseStage& stage, std::vector<double>* dofs, int level, double scale,
                  Grid grid = Grid::kNone);
  // Every stage at the coarse level, then (options.refine) at the fine one.
  void FitAll(std::vector<double>* dofs, double scale, Grid grid);
  // The legs' angles exchanged, left for right: the other phase of a stride.
  std::vector<double> LegsExchanged(const std::vector<double>& dofs) const;
  void TryLegsExchanged(std::vector<double>* dofs);
  // Replaces *dofs by `trial` where the whole body's objective at the fine
  // level is below `factor` times that of *dofs.
  void KeepIfFitsBetter(std::vector<double>* dofs, const std::vector<double>& trial, double factor);
  // Each limb searched again from a wide grid; kept where the body fits better.
  void Recover(std::vector<double>* dofs, FrameFit* fit);
  // Silhouette IoU and XOR at the fine level (a full redraw), the keypoint
  // distance, and the flags.
  void Measure(const std::vector<double>& dofs, FrameFit* fit);
  // The mean distance of the model's joints from the sightings, in shares of
  // the actor's height in each image (-1 without sightings).
  double KeypointDistance(const std::vector<double>& dofs) const;

 private:
  void BuildStages();
};

}  // namespace fvv

#endif  // FVV_ENCODER_TRACK_POSE_FITTER_H_
