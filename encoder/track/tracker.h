// Marker-free motion capture from silhouettes and, where a keypoint network
// or a person has marked them, 2D joint sightings: the generic body model is
// fitted to every frame by minimising the number of pixels in the XOR of its
// rendered silhouette and the image silhouettes, summed over cameras, plus
// the distance of its projected joints from the sightings (a robust term:
// sightings place the body, silhouettes make it fit).
//
// Initialisation (encoder/track/body_initialiser.h) places the actor and fits
// its proportions; every later frame starts from a damped constant-velocity
// prediction and runs the per-frame fit (encoder/track/pose_fitter.h). A frame
// that fits poorly, or whose joints disagree with the sightings, is searched
// again from wide grids before it is flagged.
#ifndef FVV_ENCODER_TRACK_TRACKER_H_
#define FVV_ENCODER_TRACK_TRACKER_H_

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "codec/base/status.h"
#include "container/cameras.h"
#include "encoder/body/generic_body.h"
#include "encoder/io/image_io.h"
#include "encoder/track/joint_sighting.h"

namespace fvv {

struct TrackerOptions {
  unsigned threads = 2;
  bool adapt_shape = true;  // fit stature, girth and limb lengths at initialisation
  // The actor's shape, settled elsewhere (a take's shared pass before it is
  // tracked in shards): the first frame is searched as with adapt_shape, then
  // its pose fitted with this shape, which is never changed after.
  std::optional<BodyShape> fixed_shape;
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
  // The keypoint term, per unit of squared error (shares of the actor's
  // height) per sighting: a share of the camera's silhouette area. Errors
  // beyond `keypoint_reach` count less and less (a wrong sighting).
  double keypoint_weight = 8.0;
  double keypoint_reach = 0.1;
  // A frame whose joints are further than this from the sightings on average
  // (shares of the actor's height) is searched again, then flagged.
  double keypoint_disagreement = 0.06;
  // The working resolution: images are reduced by the integer factor (2 at
  // least) that brings the actor's height at the fine level nearest this many
  // pixels (the coarse level is half as large again); set at initialisation.
  int fine_height = 200;
};

struct FrameFit {
  std::vector<double> dofs;  // Skeleton::Dofs() order of the generic body
  double xor_ratio = 0;      // XOR pixels / silhouette pixels, over all usable cameras
  double iou = 0;            // intersection over union of the silhouettes
  int cameras_used = 0;      // cameras with a non-empty silhouette
  bool poor = false;         // flagged: fit too poor to trust
  std::string note;          // why it is flagged
  int evaluations = 0;       // objective evaluations spent
  // Mean distance of the joints from the sightings, in shares of the actor's
  // height in each image (-1: no sightings).
  double keypoint_distance = -1;
};

class Tracker {
 public:
  static StatusOr<std::unique_ptr<Tracker>> Create(
      std::vector<Camera> cameras, const TrackerOptions& options = TrackerOptions());
  ~Tracker();

  // The first frame: global pose from the sightings triangulated (or the
  // silhouettes' geometry without them), then the body shape (when
  // adapt_shape) and the full pose. Silhouettes: one per camera, grey,
  // non-zero = actor, at the cameras' image size. Sightings: one list per
  // camera, or none at all.
  StatusOr<FrameFit> Initialise(const std::vector<Image>& silhouettes,
                                const std::vector<std::vector<JointSighting>>& sightings = {});
  // Instead of Initialise: tracking goes on from poses another run fitted to
  // the two frames before (a shard after its neighbour's part), with
  // options.fixed_shape (required). `silhouettes` (the next frame's) set the
  // working resolution as Initialise's do.
  Status Resume(const std::vector<double>& previous, const std::vector<double>& last,
                const std::vector<Image>& silhouettes);
  // Every later frame, from the prediction.
  StatusOr<FrameFit> Track(const std::vector<Image>& silhouettes,
                           const std::vector<std::vector<JointSighting>>& sightings = {});

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

// The silhouette of `model` posed at `dofs` in `camera` (its image size,
// 0/255): for overlays, and to score a fit in a camera it did not use.
Image BodySilhouette(const BodyModel& model, const Camera& camera, const std::vector<double>& dofs);

}  // namespace fvv

#endif  // FVV_ENCODER_TRACK_TRACKER_H_
