#include "encoder/track/silhouette_calibration.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "encoder/capture/calibration.h"

namespace fvv {

Camera TurnedByImageShift(const Camera& camera, const Eigen::Vector2d& pixels) {
  // A point on the optical axis at depth z moves by (wy z, -wx z) under the
  // small turn w: in pixels (fx wy, -fy wx).
  const Eigen::Vector3d w(-pixels.y() / camera.fy, pixels.x() / camera.fx, 0);
  const Eigen::Matrix3d turn = w.norm() < 1e-15
                                   ? Eigen::Matrix3d::Identity()
                                   : Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
  const Eigen::Matrix3d r = turn * CameraRotation(camera);
  const Eigen::Vector3d centre = CameraCentre(camera);
  const Eigen::Vector3d t = -r * centre;
  Camera out = camera;
  for (int i = 0; i < 9; ++i) out.rotation[size_t(i)] = r(i / 3, i % 3);
  for (int i = 0; i < 3; ++i) out.translation[size_t(i)] = t[i];
  return out;
}

double TurnBetween(const Camera& a, const Camera& b) {
  const Eigen::AngleAxisd d(CameraRotation(a) * CameraRotation(b).transpose());
  return std::abs(d.angle()) * 180 / M_PI;
}

StatusOr<SilhouetteCalibration> RefineCamerasFromSilhouettes(
    const Capture& capture, const SilhouetteCalibrationOptions& o) {
  const size_t n = capture.cameras.size();
  if (n < 2) return InvalidArgument("refine-calib: needs 2 cameras or more");
  if (o.rounds < 1 || o.rounds > 20) return InvalidArgument("refine-calib: 1 to 20 rounds");
  const uint32_t last = std::min(o.last, capture.frame_count - 1);
  if (o.first > last || last - o.first + 1 < 3) {
    return InvalidArgument("refine-calib: frames " + std::to_string(o.first) + ".." +
                           std::to_string(o.last) +
                           ": a camera's shift needs 3 frames or more of the capture");
  }
  SilhouetteCalibration result;
  Capture current = capture;
  TrackCaptureOptions t = o.track;
  t.first = o.first;
  t.last = last;
  t.separate_frames.clear();
  t.shift_check_every = 1;  // every frame's outline counts
  t.step_check_frames = 0;
  t.on_frame = nullptr;
  for (int round = 0; round < o.rounds; ++round) {
    if (o.progress) {
      o.progress("round " + std::to_string(round + 1) + ": tracking frames " +
                 std::to_string(o.first) + ".." + std::to_string(last));
    }
    StatusOr<TrackCaptureResult> tracked = TrackCapture(current, t);
    if (!tracked.ok()) return tracked.status();
    SilhouetteCalibrationRound r;
    r.mean_iou = tracked->mean_iou;
    double largest = 0;
    for (size_t c = 0; c < n; ++c) {
      const SilhouetteShift& s = tracked->camera_shifts[c].shift;
      r.shift_px.push_back(s.pixels);
      r.iou.push_back(s.iou);
      r.shifted_iou.push_back(s.shifted_iou);
      largest = std::max(largest, s.pixels.norm());
    }
    if (o.progress) {
      char head[64];
      std::snprintf(head, sizeof(head), "round %d: mean IoU %.3f; shifts", round + 1, r.mean_iou);
      std::string line = head;
      for (size_t c = 0; c < n; ++c) {
        char part[96];
        std::snprintf(part, sizeof(part), " %s %+.1f,%+.1f px",
                      current.cameras[c].calibration.name.c_str(), r.shift_px[c].x(),
                      r.shift_px[c].y());
        line += part;
      }
      o.progress(line);
    }
    result.rounds.push_back(r);
    if (largest < o.stop_px) break;
    for (size_t c = 0; c < n; ++c) {
      Camera& k = current.cameras[c].calibration;
      k = TurnedByImageShift(k, r.shift_px[c]);
    }
  }
  for (size_t c = 0; c < n; ++c) {
    result.cameras.push_back(current.cameras[c].calibration);
    result.turn_deg.push_back(TurnBetween(capture.cameras[c].calibration, result.cameras[c]));
    if (result.turn_deg[c] > o.max_turn_deg) {
      char turn[96];
      std::snprintf(turn, sizeof(turn), " would turn %.2f degrees (more than %.2f)",
                    result.turn_deg[c], o.max_turn_deg);
      return InvalidArgument("refine-calib: camera " + result.cameras[c].name + turn +
                             ": the calibration is wrong in another way than a bumped camera "
                             "(another take's file, a unit, an axis), or the fit is (fvv track "
                             "--overlays)");
    }
  }
  return result;
}

}  // namespace fvv
