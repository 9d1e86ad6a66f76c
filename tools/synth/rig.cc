#include "tools/synth/rig.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "encoder/body/kinematics.h"
#include "encoder/capture/calibration.h"
#include "encoder/capture/capture.h"
#include "encoder/encode/pose_file.h"

namespace fvv {

Eigen::Vector3d NearestPointToAxes(const std::vector<Camera>& cameras) {
  // Sum over cameras of (I - a a^T) (x - c) = 0: the point whose squared
  // distances to the axes (centre c, direction a) add up least.
  Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero(), mean = Eigen::Vector3d::Zero();
  for (const Camera& cam : cameras) {
    const Eigen::Vector3d c = CameraCentre(cam);
    const Eigen::Vector3d a = CameraRotation(cam).row(2).transpose().normalized();
    const Eigen::Matrix3d p = Eigen::Matrix3d::Identity() - a * a.transpose();
    m += p, b += p * c, mean += c;
  }
  Eigen::Vector3d x = mean / std::max<size_t>(1, cameras.size());
  const Eigen::FullPivLU<Eigen::Matrix3d> lu(m);
  if (cameras.size() >= 2 && lu.rank() == 3) x = lu.solve(b);
  return Eigen::Vector3d(x.x(), 0, x.z());
}

StatusOr<Rig> LoadRig(const std::string& capture, const std::string& poses, uint32_t frames) {
  StatusOr<Capture> c = LoadCapture(capture);
  if (!c.ok()) return Status(c.status().code(), "synth: --rig: " + c.status().message());
  if (c->cameras.empty()) return InvalidArgument("synth: --rig " + capture + ": no cameras");
  Rig rig;
  for (const CaptureCamera& cc : c->cameras) {
    Camera cam = cc.calibration;
    if (cam.width < 16 || cam.height < 16 || cam.width > 4096 || cam.height > 4096) {
      return InvalidArgument("synth: --rig: camera " + cam.name + " is " +
                             std::to_string(cam.width) + "x" + std::to_string(cam.height) +
                             " (16..4096 on each side)");
    }
    cam.distortion = {};
    rig.cameras.push_back(cam);
  }
  Eigen::Vector3d centre = NearestPointToAxes(rig.cameras);
  if (!poses.empty()) {
    StatusOr<PoseSequence> p = LoadPoseFile(poses);
    if (!p.ok()) return Status(p.status().code(), "synth: --rig-poses: " + p.status().message());
    if (p->poses.size() < frames) {
      return InvalidArgument("synth: --rig-poses " + poses + " holds " +
                             std::to_string(p->poses.size()) + " frames, " +
                             std::to_string(frames) + " asked for");
    }
    const Skeleton skeleton = MakeGenericSkeleton(p->shape);
    const int x = DofIndex(skeleton, kRoot, 3), z = DofIndex(skeleton, kRoot, 5);
    if (x < 0 || z < 0) return Internal("synth: the body model has no root translation");
    rig.poses.assign(p->poses.begin(), p->poses.begin() + frames);
    centre.setZero();
    for (const auto& f : rig.poses) centre += Eigen::Vector3d(f[x], 0, f[z]);
    centre /= double(frames);
    for (auto& f : rig.poses) f[x] -= centre.x(), f[z] -= centre.z();
    rig.shape = p->shape;
  }
  // The world moves by -centre: x_cam = R (x' + centre) + t.
  rig.moved_by = -centre;
  for (Camera& cam : rig.cameras) {
    const Eigen::Vector3d t =
        Eigen::Map<const Eigen::Vector3d>(cam.translation.data()) + CameraRotation(cam) * centre;
    cam.translation = {t.x(), t.y(), t.z()};
  }
  return rig;
}

}  // namespace fvv
