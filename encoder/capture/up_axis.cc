#include "encoder/capture/up_axis.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <cstdio>

#include "encoder/capture/calibration.h"

namespace fvv {
namespace {

const char kAxisNames[3] = {'x', 'y', 'z'};

std::string AxisName(int axis, int sign) {
  return std::string(sign > 0 ? "+" : "-") + kAxisNames[axis];
}

// The signed world axis nearest `v`.
void NearestAxis(const Eigen::Vector3d& v, int* axis, int* sign) {
  v.cwiseAbs().maxCoeff(axis);
  *sign = v[*axis] >= 0 ? 1 : -1;
}

}  // namespace

std::string UpAxisEvidence::Describe() const {
  if (!found) return "the cameras give no clear up";
  char line[160];
  if (from_centres) {
    std::snprintf(line, sizeof(line),
                  "%s: the normal of the cameras' centres, on the side they look down from",
                  AxisName(axis, sign).c_str());
  } else {
    std::snprintf(line, sizeof(line), "%s: %u camera(s)' image up within 45 degrees of it",
                  AxisName(axis, sign).c_str(), upright);
  }
  return line;
}

UpAxisEvidence InferUpAxis(const std::vector<Camera>& cameras) {
  UpAxisEvidence e;
  if (cameras.empty()) return e;
  // Image up in the world: the camera's -y axis (OpenCV: y points down the image).
  Eigen::Vector3d mean_up = Eigen::Vector3d::Zero(), mean_view = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> ups, centres;
  for (const Camera& c : cameras) {
    const Eigen::Matrix3d r = CameraRotation(c);
    ups.push_back(-r.row(1).transpose());
    mean_up += ups.back();
    mean_view += r.row(2).transpose();
    centres.push_back(CameraCentre(c));
  }
  mean_up /= double(cameras.size());
  mean_view /= double(cameras.size());
  NearestAxis(mean_up, &e.axis, &e.sign);
  e.agreement = e.sign * mean_up[e.axis];
  for (const Eigen::Vector3d& u : ups) e.upright += e.sign * u[e.axis] > std::sqrt(0.5);
  // Most cameras upright: their image up decides.
  if (e.agreement >= 0.5 && 2 * e.upright > cameras.size()) {
    e.found = true;
    return e;
  }
  // Rolled cameras: the plane of their centres, if they span one.
  if (cameras.size() < 3) return e;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : centres) mean += p;
  mean /= double(centres.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& p : centres) cov += (p - mean) * (p - mean).transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  const Eigen::Vector3d values = eig.eigenvalues();  // ascending
  // A ring or band: flat in one direction, wide in the other two.
  if (values[1] <= 0 || values[0] > 0.25 * values[1]) return e;
  Eigen::Vector3d normal = eig.eigenvectors().col(0);
  // Cameras look across or down: the normal points against their mean view.
  const double down = normal.dot(mean_view);
  if (std::abs(down) < 0.05) return e;
  if (down > 0) normal = -normal;
  NearestAxis(normal, &e.axis, &e.sign);
  if (std::abs(normal[e.axis]) < std::sqrt(0.5)) return e;  // a slanted ring: no axis
  e.agreement = e.sign * mean_up[e.axis];
  e.upright = 0;
  for (const Eigen::Vector3d& u : ups) e.upright += e.sign * u[e.axis] > std::sqrt(0.5);
  e.from_centres = true;
  e.found = true;
  return e;
}

UpAxisChoice ChooseUpAxis(const std::string& requested, char format_up, const std::string& format,
                          const std::vector<Camera>& cameras) {
  const UpAxisEvidence e = InferUpAxis(cameras);
  UpAxisChoice c;
  const bool cameras_say = e.found && e.sign > 0 && e.axis != 0;
  if (requested == "y" || requested == "z") {
    c.axis = requested[0];
    c.reason = "as --up says";
  } else if (format_up != 0) {
    c.axis = format_up;
    c.reason = "the " + format + " format's world is " + std::string(1, format_up) + " up";
  } else if (cameras_say) {
    c.axis = kAxisNames[e.axis];
    c.reason = "from the cameras (" + e.Describe() + ")";
    return c;
  } else {
    c.axis = 'y';
    c.reason = e.found ? "y, the default: the cameras' up is " + AxisName(e.axis, e.sign) +
                             ", which capture.json cannot say (y or z up only)"
                       : "y, the default: " + e.Describe();
    c.warning =
        "check that the actor stands upright (fvv capture hull, fvv track --overlays); "
        "give --up if not";
    return c;
  }
  if (e.found && !(e.sign > 0 && kAxisNames[e.axis] == c.axis)) {
    c.warning = "the cameras' image up points along " + AxisName(e.axis, e.sign) + " (" +
                e.Describe() + "), not +" + std::string(1, c.axis) +
                ": with this up the actor lies on his side or stands on his head";
  }
  return c;
}

std::string UprightWarning(const std::vector<CaptureCamera>& cameras, char declared_up) {
  std::vector<Camera> calibrations;
  for (const CaptureCamera& c : cameras) calibrations.push_back(c.calibration);
  const UpAxisEvidence e = InferUpAxis(calibrations);
  if (!e.found || (e.axis == 1 && e.sign > 0)) return "";
  return "the cameras do not stand upright in this capture's world (capture.json: up_axis \"" +
         std::string(1, declared_up) + "\"): their image up points along " +
         AxisName(e.axis, e.sign) + " of fvv's y-up world (" + e.Describe() +
         "), so the actor lies on his side or stands on his head; import the calibration again "
         "with --up (fvv capture import-calib)";
}

}  // namespace fvv
