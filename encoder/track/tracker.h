// Marker-free motion capture from silhouettes: the generic body
// model is fitted to every frame by minimising the number of pixels in the XOR
// of its rendered silhouette and the image silhouettes, summed over cameras.
//
// The search is hierarchical, in the order of each part's effect on the
// silhouettes and its place in the kinematic chain: root and torso, then each
// arm and leg (upper and lower parts jointly, after a small grid search over
// the upper joint to escape local minima), then hands, feet and head. Each
// stage runs Powell's method, first on quarter-resolution silhouettes and then
// on half resolution. Only what a stage moves is rasterised: the silhouettes
// of the fixed parts are drawn once per stage and the XOR is counted inside the
// moving parts' bounding box (the rest comes from an integral image). A
// penalty on overlapping bounding capsules forbids limbs passing through the
// torso or each other; each frame starts from a damped constant-velocity
// prediction. Cameras are evaluated in parallel.
#ifndef FVV_ENCODER_TRACK_TRACKER_H_
#define FVV_ENCODER_TRACK_TRACKER_H_

#include <memory>
#include <string>
#include <vector>

#include "codec/base/status.h"
#include "container/cameras.h"
#include "encoder/body/generic_body.h"
#include "encoder/io/image_io.h"

namespace fvv {

struct TrackerOptions {
  unsigned threads = 2;
  bool adapt_shape = true;  // fit stature, girth and limb lengths at initialisation
  // Below this IoU with the generic body's proportions at initialisation, the
  // actor is fitted again with proportions of its own (head, trunk, arms and
  // legs: length and girth each) and the better fit kept.
  double proportions_iou = 0.85;
  double poor_fit = 0.35;       // XOR / silhouette area above this flags a frame
  int stage_evaluations = 160;  // Powell budget per stage and resolution
  bool refine = true;           // second pass at half resolution
  double retry_iou = 0.94;      // below this IoU, limbs are searched again from a wide grid
  double smoothness = 0.02;  // pull towards the prediction: share of the silhouette area per rad^2
  // With proportions of its own, the actor's arm length is fitted again over
  // this many tracked frames, every arm_refit_spacing-th (0: never; a spacing
  // under 1 counts as 1). The kept frames' silhouettes are held until then
  // (about 6 MB a frame for 8 cameras at 640x480).
  int arm_refit_frames = 5;
  int arm_refit_spacing = 3;
  // At initialisation and in the recovery pass, the legs' angles are tried
  // exchanged, left for right (the other phase of a stride), and kept where
  // the silhouettes fit better: a fit can reach each foot with the other leg,
  // the legs crossed, and stay there.
  bool exchange_legs = true;
};

struct FrameFit {
  std::vector<double> dofs;  // Skeleton::Dofs() order of the generic body
  double xor_ratio = 0;      // XOR pixels / silhouette pixels, over all usable cameras
  double iou = 0;            // intersection over union of the silhouettes
  int cameras_used = 0;      // cameras with a non-empty silhouette
  bool poor = false;         // flagged: fit too poor to trust
  std::string note;          // why it is flagged
  int evaluations = 0;       // objective evaluations spent
};

class Tracker {
 public:
  static StatusOr<std::unique_ptr<Tracker>> Create(
      std::vector<Camera> cameras, const TrackerOptions& options = TrackerOptions());
  ~Tracker();

  // The first frame: global pose from the silhouettes' geometry, then the body
  // shape (when adapt_shape) and the full pose. Silhouettes: one per camera,
  // grey, non-zero = actor, at the cameras' image size.
  StatusOr<FrameFit> Initialise(const std::vector<Image>& silhouettes);
  // Every later frame, from the prediction.
  StatusOr<FrameFit> Track(const std::vector<Image>& silhouettes);

  // The tracking model's silhouette in camera `camera` at `dofs` (full image
  // size, 0/255): for overlays that show how well a frame fits.
  Image ModelSilhouette(uint32_t camera, const std::vector<double>& dofs) const;

  const BodyShape& shape() const;
  // The generic body (full resolution) with the fitted shape.
  BodyModel Model() const;

 private:
  struct Impl;
  explicit Tracker(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace fvv

#endif  // FVV_ENCODER_TRACK_TRACKER_H_
