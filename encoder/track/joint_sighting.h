// A body joint seen in one camera image: what a 2D keypoint network reports,
// or a person marks, in the generic body's terms.
#ifndef FVV_ENCODER_TRACK_JOINT_SIGHTING_H_
#define FVV_ENCODER_TRACK_JOINT_SIGHTING_H_

#include <Eigen/Core>

namespace fvv {

// Which of the generic body's joints (GenericJoint), where (pixels as the
// calibration's, lens distortion included) and how sure (0..1).
struct JointSighting {
  int joint = 0;
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();
  double confidence = 0;
};

}  // namespace fvv

#endif  // FVV_ENCODER_TRACK_JOINT_SIGHTING_H_
