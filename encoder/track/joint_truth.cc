#include "encoder/track/joint_truth.h"

#include <sys/stat.h>

#include <map>
#include <nlohmann/json.hpp>

#include "encoder/body/kinematics.h"
#include "encoder/io/image_io.h"

namespace fvv {
namespace {

// Generic joint -> the corresponding joint of known third-party characters.
const std::map<std::string, std::vector<std::string>>& Correspondences() {
  static const std::map<std::string, std::vector<std::string>> k = {
      {"l_hip", {"leg_joint_L_1", "mixamorig:LeftUpLeg", "LeftUpLeg"}},
      {"l_knee", {"leg_joint_L_2", "mixamorig:LeftLeg", "LeftLeg"}},
      {"l_ankle", {"leg_joint_L_3", "mixamorig:LeftFoot", "LeftFoot"}},
      {"r_hip", {"leg_joint_R_1", "mixamorig:RightUpLeg", "RightUpLeg"}},
      {"r_knee", {"leg_joint_R_2", "mixamorig:RightLeg", "RightLeg"}},
      {"r_ankle", {"leg_joint_R_3", "mixamorig:RightFoot", "RightFoot"}},
      {"l_shoulder", {"Skeleton_arm_joint_L__4_", "mixamorig:LeftArm", "LeftArm"}},
      {"l_elbow", {"Skeleton_arm_joint_L__3_", "mixamorig:LeftForeArm", "LeftForeArm"}},
      {"l_wrist", {"Skeleton_arm_joint_L__2_", "mixamorig:LeftHand", "LeftHand"}},
      {"r_shoulder", {"Skeleton_arm_joint_R", "mixamorig:RightArm", "RightArm"}},
      {"r_elbow", {"Skeleton_arm_joint_R__2_", "mixamorig:RightForeArm", "RightForeArm"}},
      {"r_wrist", {"Skeleton_arm_joint_R__3_", "mixamorig:RightHand", "RightHand"}},
      {"neck", {"Skeleton_neck_joint_1", "mixamorig:Neck", "Neck"}},
  };
  return k;
}

bool IsDir(const std::string& p) {
  struct stat st;
  return stat(p.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

}  // namespace

std::string JointErrors::Describe() const {
  std::string s;
  for (const std::string& j : joints) s += (s.empty() ? "" : ", ") + j;
  return s;
}

StatusOr<JointErrors> CompareWithTruth(const std::string& truth, const Skeleton& generic,
                                       const std::vector<std::vector<double>>& poses,
                                       uint32_t first_frame) {
  std::string path = truth;
  if (IsDir(path))
    path = IsDir(path + "/truth") ? path + "/truth/truth.json" : path + "/truth.json";
  StatusOr<std::vector<uint8_t>> bytes = ReadFileBytes(path, 512u << 20);
  if (!bytes.ok()) return Status(bytes.status().code(), "truth: " + bytes.status().message());
  const nlohmann::json j = nlohmann::json::parse(bytes->begin(), bytes->end(), nullptr, false);
  if (j.is_discarded() || !j.contains("frames") || !j["frames"].is_array()) {
    return Corrupt("truth " + path + ": not a truth.json (no frames)");
  }
  const nlohmann::json& frames = j["frames"];
  if (first_frame + poses.size() > frames.size()) {
    return InvalidArgument("truth " + path + ": has " + std::to_string(frames.size()) +
                           " frames, poses reach " + std::to_string(first_frame + poses.size()));
  }
  // Which truth joint each generic joint is compared with.
  const nlohmann::json& names = frames[0]["joints"];
  std::vector<std::pair<int, std::string>> pairs;
  for (size_t b = 0; b < generic.bones.size(); ++b) {
    const std::string& g = generic.bones[b].name;
    if (names.contains(g)) {
      pairs.push_back({int(b), g});
      continue;
    }
    auto it = Correspondences().find(g);
    if (it == Correspondences().end()) continue;
    for (const std::string& other : it->second) {
      if (names.contains(other)) {
        pairs.push_back({int(b), other});
        break;
      }
    }
  }
  if (pairs.empty())
    return InvalidArgument("truth " + path + ": no joint corresponds to the body model's");
  JointErrors e;
  for (const auto& p : pairs) e.joints.push_back(generic.bones[p.first].name);
  e.per_joint_mean.assign(pairs.size(), 0.0);
  e.per_joint_offset.assign(pairs.size(), Eigen::Vector3d::Zero());
  double sum = 0;
  size_t count = 0;
  for (size_t i = 0; i < poses.size(); ++i) {
    const std::vector<Eigen::Vector3d> ours = JointPositions(generic, poses[i]);
    const nlohmann::json& theirs = frames[first_frame + i]["joints"];
    double frame_sum = 0;
    for (size_t k = 0; k < pairs.size(); ++k) {
      const auto& v = theirs[pairs[k].second];
      const Eigen::Vector3d t(v[0].get<double>(), v[1].get<double>(), v[2].get<double>());
      const Eigen::Vector3d diff = ours[pairs[k].first] - t;
      const double d = diff.norm();
      e.per_joint_mean[k] += d / poses.size();
      e.per_joint_offset[k] += diff / double(poses.size());
      frame_sum += d;
      e.max = std::max(e.max, d);
    }
    e.per_frame.push_back(frame_sum / pairs.size());
    sum += frame_sum;
    count += pairs.size();
  }
  e.mean = count ? sum / count : 0;
  return e;
}

}  // namespace fvv
