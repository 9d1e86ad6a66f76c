#include "encoder/track/camera_choice.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

#include "encoder/capture/calibration.h"

namespace fvv {

Eigen::Vector3d CaptureVolumeCentre(const std::vector<Camera>& cameras) {
  Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (const Camera& c : cameras) {
    const Eigen::Vector3d d = CameraRotation(c).row(2).transpose().normalized();
    const Eigen::Matrix3d p = Eigen::Matrix3d::Identity() - d * d.transpose();
    a += p;
    b += p * CameraCentre(c);
  }
  // Parallel axes (one camera, or all looking one way) leave the system
  // singular: the cameras' mean centre then.
  Eigen::FullPivLU<Eigen::Matrix3d> lu(a);
  if (cameras.size() < 2 || lu.rank() < 3) {
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const Camera& c : cameras) mean += CameraCentre(c);
    return cameras.empty() ? mean : Eigen::Vector3d(mean / double(cameras.size()));
  }
  return lu.solve(b);
}

CameraChoice ChooseTrackingCameras(const std::vector<Camera>& cameras, uint32_t count) {
  CameraChoice choice;
  const uint32_t n = uint32_t(cameras.size());
  choice.centre = CaptureVolumeCentre(cameras);
  // The volume's outline: two circles and the middle one, 12 points each.
  std::vector<Eigen::Vector3d> outline;
  for (double dy : {-0.95, 0.0, 1.0}) {
    for (int k = 0; k < 12; ++k) {
      const double a = 2 * M_PI * k / 12;
      outline.push_back(choice.centre +
                        Eigen::Vector3d(0.45 * std::cos(a), dy, 0.45 * std::sin(a)));
    }
  }
  choice.coverage.assign(n, 0);
  for (uint32_t c = 0; c < n; ++c) {
    int inside = 0;
    for (const Eigen::Vector3d& p : outline) {
      Eigen::Vector2d px;
      inside += ProjectPoint(cameras[c], p, &px) && px.x() >= 0 && px.y() >= 0 &&
                px.x() <= cameras[c].width - 1.0 && px.y() <= cameras[c].height - 1.0;
    }
    choice.coverage[c] = double(inside) / double(outline.size());
  }
  if (count >= n) {
    for (uint32_t c = 0; c < n; ++c) choice.cameras.push_back(c);
    return choice;
  }
  // Candidates: every camera seeing the volume whole; where they are too
  // few, the next best seeing most of it.
  std::vector<uint32_t> order(n);
  for (uint32_t c = 0; c < n; ++c) order[c] = c;
  std::stable_sort(order.begin(), order.end(),
                   [&](uint32_t a, uint32_t b) { return choice.coverage[a] > choice.coverage[b]; });
  size_t whole = 0;
  while (whole < n && choice.coverage[order[whole]] >= 1.0) ++whole;
  order.resize(std::max<size_t>(whole, count));
  std::vector<Eigen::Vector3d> direction;
  double mean_height = 0;
  for (uint32_t c : order) {
    direction.push_back((CameraCentre(cameras[c]) - choice.centre).normalized());
    mean_height += direction.back().y();
  }
  mean_height /= double(order.size());
  std::vector<bool> taken(order.size(), false);
  std::vector<double> nearest(order.size(), std::numeric_limits<double>::infinity());
  size_t next = 0;
  for (size_t i = 1; i < order.size(); ++i) {
    if (std::abs(direction[i].y() - mean_height) < std::abs(direction[next].y() - mean_height)) {
      next = i;
    }
  }
  for (uint32_t k = 0; k < count; ++k) {
    taken[next] = true;
    choice.cameras.push_back(order[next]);
    // Each candidate's angle to the nearest camera taken; the farthest next.
    size_t best = order.size();
    for (size_t i = 0; i < order.size(); ++i) {
      if (taken[i]) continue;
      const double angle = std::acos(std::clamp(direction[i].dot(direction[next]), -1.0, 1.0));
      nearest[i] = std::min(nearest[i], angle);
      if (best == order.size() || nearest[i] > nearest[best]) best = i;
    }
    if (best == order.size()) break;
    next = best;
  }
  std::sort(choice.cameras.begin(), choice.cameras.end());
  return choice;
}

StatusOr<uint32_t> ParseTrackingCameras(const std::string& text) {
  if (text == "auto") return kTrackingCamerasAuto;
  if (text == "all") return kTrackingCamerasAll;
  char* end = nullptr;
  const long v = std::strtol(text.c_str(), &end, 10);
  if (end == text.c_str() || *end != '\0' || v < 1 || v > 256) {
    return InvalidArgument("--track-cameras: a count of 1 to 256, all or auto, not \"" + text +
                           "\"");
  }
  return uint32_t(v);
}

uint32_t TrackingCameraCount(uint32_t setting, size_t rig_size) {
  const uint32_t n = uint32_t(rig_size);
  if (setting == kTrackingCamerasAuto) return n > kAutoTrackingAbove ? kDefaultTrackingCameras : n;
  return std::min(n, setting);
}

Capture FittingCapture(const Capture& capture, uint32_t count, std::string* names) {
  if (names) names->clear();
  if (count >= capture.cameras.size()) return capture;
  std::vector<Camera> calibrations;
  for (const CaptureCamera& c : capture.cameras) calibrations.push_back(c.calibration);
  Capture fit = capture;
  fit.cameras.clear();
  for (uint32_t c : ChooseTrackingCameras(calibrations, count).cameras) {
    fit.cameras.push_back(capture.cameras[c]);
    if (names) *names += (names->empty() ? "" : " ") + capture.cameras[c].calibration.name;
  }
  return fit;
}

}  // namespace fvv
