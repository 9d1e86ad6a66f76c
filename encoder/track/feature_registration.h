// Model registration from feature points: the generic
// body's pose and proportions fitted to 3D joint centres reconstructed from
// the cameras' feature points. First an analytic initialisation, top-down
// through the skeleton: the root's rotation by the best rotation of its child
// joints' directions onto the observed ones (Kabsch), its translation from the
// observed hips or root, then every bone the same way from its own joint and
// the observed joints of its children (for a limb, the joint triple
// shoulder-elbow-wrist or hip-knee-ankle sets the upper bone's direction and
// the bend); the proportions start from the observed bone lengths. Then a
// bound-constrained Levenberg-Marquardt least-squares fit (Eigen) of every
// DOF and the segment length scales (left and right sides sharing one) plus
// shoulder and hip width, within the DOF limits and the shape's bounds.
#ifndef FVV_ENCODER_TRACK_FEATURE_REGISTRATION_H_
#define FVV_ENCODER_TRACK_FEATURE_REGISTRATION_H_

#include <map>
#include <string>
#include <vector>

#include "codec/base/status.h"
#include "encoder/body/generic_body.h"
#include "encoder/track/features.h"

namespace fvv {

struct RegistrationOptions {
  bool fit_shape = true;      // fit proportions; else keep the start shape
  int iterations = 100;       // Levenberg-Marquardt steps at most
  double shape_prior = 1e-4;  // m^2 per unit of scale^2 pulling scales to the start shape
};

struct Registration {
  std::vector<double> dofs;  // generic-body DOF order
  BodyShape shape;
  double rms_m = 0;          // joint residual after the fit
  double initial_rms_m = 0;  // after the analytic initialisation
  int joints = 0;            // observed joints used
};

// `features` are 3D joint centres by generic joint name (at least 4, among
// them enough of the trunk to fix its orientation: three of root, hips,
// lumbar, thoracic, neck, shoulders). `initial` (may be empty): DOFs to start
// the fit from instead of the analytic initialisation (the previous frame's).
StatusOr<Registration> RegisterSkeleton(const std::map<std::string, Feature3D>& features,
                                        const BodyShape& start, const std::vector<double>& initial,
                                        const RegistrationOptions& options = {});

// The analytic initialisation alone.
std::vector<double> InitialisePose(const Skeleton& skeleton,
                                   const std::map<std::string, Feature3D>& features);

}  // namespace fvv

#endif  // FVV_ENCODER_TRACK_FEATURE_REGISTRATION_H_
