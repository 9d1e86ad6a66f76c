// The tracker's first frame (internal to encoder/track): where the actor
// stands, which way it faces, its build and its pose. With joint sightings in
// two or more cameras, the joints are triangulated (a wrong view left out) and
// the generic body registered to them (encoder/track/feature_registration.h):
// pose and proportions at once. Without, from the silhouettes alone: the
// point the silhouettes' rays agree on, a heading search with the trunk, and
// the build fitted with the pose. Either way the silhouettes then make it fit.
// Also the arms' length refitted over tracked frames, for an actor built
// unlike the generic body.
#ifndef FVV_ENCODER_TRACK_BODY_INITIALISER_H_
#define FVV_ENCODER_TRACK_BODY_INITIALISER_H_

#include <Eigen/Core>
#include <utility>
#include <vector>

#include "codec/base/status.h"
#include "encoder/track/pose_fitter.h"

namespace fvv {

class BodyInitialiser {
 public:
  explicit BodyInitialiser(PoseFitter* fitter) : fit_(*fitter) {}

  // The first frame, set in the fitter (SetFrame, SetWeights) with
  // `silhouettes` at full resolution. Leaves the fitter's shape and model
  // fitted; returns the pose.
  StatusOr<std::vector<double>> Initialise(const std::vector<Image>& silhouettes);
  // Whether the actor got proportions of its own (not only the generic
  // body's, scaled).
  bool own_proportions() const { return own_proportions_; }

  // A tracked frame kept to fit the arms' length over several.
  struct KeptFrame {
    PoseFitter::Frame frame;
    std::vector<double> dofs;
  };
  // The arms' length over the kept frames (their arms' poses fitted again).
  void RefitArmLength(std::vector<KeptFrame>* kept);

 private:
  bool Locate(const std::vector<Image>& sils, Eigen::Vector3d* centre, double* height);
  // The body registered to the triangulated sightings; false when too few
  // joints are seen by two cameras.
  bool PlaceBySightings(std::vector<double>* dofs);
  std::vector<double> NeutralPose(const Eigen::Vector3d& centre, double yaw) const;
  void FitSize(std::vector<double>* dofs);
  std::vector<std::vector<double>> Headings(const Eigen::Vector3d& centre, const PoseStage& stage);
  std::vector<double> Turned(const Eigen::Vector3d& centre, const std::vector<double>& from,
                             double turn, const PoseStage& stage);
  std::vector<std::vector<double>> Starts(const Eigen::Vector3d& centre, const PoseStage& stage,
                                          const std::vector<double>* placed);
  // From `start` (the placed body) or, when null, a heading search.
  std::vector<double> InitialiseScaled(const Eigen::Vector3d& centre,
                                       const std::vector<double>* start, BodyShape* fitted);
  std::vector<double> InitialiseProportions(const Eigen::Vector3d& centre,
                                            const std::vector<double>* start, BodyShape* fitted);
  BodyShape InitialShape() const;
  double ShapeValue(int param) const;
  void SetShapeValue(int param, double v);
  std::pair<double, double> RestExtent() const;
  void FitShape(std::vector<double>* dofs, uint32_t params, int level, int budget);

  PoseFitter& fit_;
  double actor_height_ = 0;  // measured from the silhouettes
  bool own_proportions_ = false;
};

}  // namespace fvv

#endif  // FVV_ENCODER_TRACK_BODY_INITIALISER_H_
