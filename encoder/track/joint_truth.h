// Joint position errors of tracked poses against ground truth (the truth.json
// `fvv synth` writes). Joints are matched by name: the built-in actor's joints
// are the body model's own; for glTF characters a table maps corresponding
// joints (hips, knees, ankles, shoulders, elbows, wrists, neck).
#ifndef FVV_ENCODER_TRACK_JOINT_TRUTH_H_
#define FVV_ENCODER_TRACK_JOINT_TRUTH_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "codec/base/status.h"
#include "container/body_model.h"

namespace fvv {

struct JointErrors {
  double mean = 0, max = 0;         // metres, over frames and matched joints
  std::vector<std::string> joints;  // generic joint names compared
  std::vector<double> per_frame;    // mean per frame
  // Per compared joint, over the frames: mean distance, and the mean of
  // (ours - truth), the part of the error that is a constant offset (where a
  // joint sits inside the body, or a proportion fitted wrongly) rather than
  // tracking error.
  std::vector<double> per_joint_mean;
  std::vector<Eigen::Vector3d> per_joint_offset;
  std::string Describe() const;  // "l_hip, l_knee, ..."
};

// `truth`: a truth.json, or a directory holding truth.json or truth/truth.json.
// poses[i] is frame first_frame + i.
StatusOr<JointErrors> CompareWithTruth(const std::string& truth, const Skeleton& generic,
                                       const std::vector<std::vector<double>>& poses,
                                       uint32_t first_frame);

}  // namespace fvv

#endif  // FVV_ENCODER_TRACK_JOINT_TRUTH_H_
