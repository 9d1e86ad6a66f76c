#include "encoder/track/person_selection.h"

#include <Eigen/Dense>
#include <cmath>
#include <limits>

#include "encoder/capture/calibration.h"

namespace fvv {
namespace {

struct Ray {
  Eigen::Vector3d origin, direction;
};

Ray PixelRay(const Camera& camera, const Eigen::Vector2d& pixel) {
  const Eigen::Vector3d a = UnprojectPixel(camera, pixel, 1.0);
  const Eigen::Vector3d b = UnprojectPixel(camera, pixel, 2.0);
  return {a, (b - a).normalized()};
}

// The point nearest to both rays (the midpoint of their common perpendicular);
// none for rays nearly parallel or meeting behind a camera.
std::optional<Eigen::Vector3d> Meet(const Ray& p, const Ray& q) {
  const Eigen::Vector3d w = p.origin - q.origin;
  const double b = p.direction.dot(q.direction), d = p.direction.dot(w), e = q.direction.dot(w);
  const double denominator = 1 - b * b;
  if (denominator < 1e-6) return std::nullopt;
  const double s = (b * e - d) / denominator, t = (e - b * d) / denominator;
  if (s < 0 || t < 0) return std::nullopt;
  return 0.5 * (p.origin + s * p.direction + q.origin + t * q.direction);
}

// The centre of the capture volume on the floor (y = 0): the point nearest to
// every camera's optical axis, and the cameras' mean horizontal distance from it.
void CaptureVolume(const std::vector<Camera>& cameras, Eigen::Vector3d* centre, double* radius) {
  Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (const Camera& c : cameras) {
    const Eigen::Vector3d o = CameraCentre(c);
    const Eigen::Vector3d axis = CameraRotation(c).row(2).transpose().normalized();
    const Eigen::Matrix3d m = Eigen::Matrix3d::Identity() - axis * axis.transpose();
    a += m;
    b += m * o;
  }
  *centre = cameras.size() >= 2 ? Eigen::Vector3d(a.ldlt().solve(b)) : Eigen::Vector3d::Zero();
  centre->y() = 0;
  double sum = 0;
  for (const Camera& c : cameras) {
    const Eigen::Vector3d o = CameraCentre(c);
    sum += std::hypot(o.x() - centre->x(), o.z() - centre->z());
  }
  *radius = cameras.empty() ? 1 : sum / cameras.size();
}

}  // namespace

ActorChoice ChooseActor(const std::vector<Camera>& cameras,
                        const std::vector<std::vector<HipSighting>>& candidates,
                        const std::vector<std::optional<HipSighting>>& known) {
  const size_t n = cameras.size();
  ActorChoice best;
  best.chosen.assign(n, -1);
  Eigen::Vector3d centre;
  double radius = 1;
  CaptureVolume(cameras, &centre, &radius);
  // Every camera's points: the actor's where known, else the candidates.
  std::vector<std::vector<HipSighting>> points(n);
  for (size_t c = 0; c < n; ++c) {
    if (c < known.size() && known[c]) {
      points[c] = {*known[c]};
    } else if (c < candidates.size()) {
      points[c] = candidates[c];
    }
  }
  auto near = [&](size_t c, const Eigen::Vector3d& x, int* index) {
    Eigen::Vector2d px;
    if (!ProjectPoint(cameras[c], x, &px)) return false;
    double nearest = 1;  // in tolerances
    *index = -1;
    for (size_t i = 0; i < points[c].size(); ++i) {
      const double d = (points[c][i].hips - px).norm() / points[c][i].tolerance;
      if (d < nearest) nearest = d, *index = int(i);
    }
    return *index >= 0;
  };
  double best_distance = std::numeric_limits<double>::infinity();
  bool best_anchored = false;
  for (size_t a = 0; a < n; ++a) {
    for (size_t b = a + 1; b < n; ++b) {
      for (const HipSighting& pa : points[a]) {
        for (const HipSighting& pb : points[b]) {
          const std::optional<Eigen::Vector3d> x =
              Meet(PixelRay(cameras[a], pa.hips), PixelRay(cameras[b], pb.hips));
          if (!x || x->y() < -0.5 || x->y() > 2.5) continue;  // hips between floor and 2.5 m
          int agreeing = 0;
          bool anchored = false;
          std::vector<int> chosen(n, -1);
          for (size_t c = 0; c < n; ++c) {
            int index;
            if (!near(c, *x, &index)) continue;
            ++agreeing;
            if (c < known.size() && known[c]) {
              anchored = true;
            } else {
              chosen[c] = index;
            }
          }
          // Through the cameras that already follow the actor first; then more
          // cameras agreeing; then nearest the volume's centre.
          const double distance = std::hypot(x->x() - centre.x(), x->z() - centre.z());
          const bool better = anchored > best_anchored ||
                              (anchored == best_anchored &&
                               (agreeing > best.cameras_agreeing ||
                                (agreeing == best.cameras_agreeing && distance < best_distance)));
          if (agreeing >= 2 && better && distance < radius) {
            best.hips = *x;
            best.chosen = chosen;
            best.cameras_agreeing = agreeing;
            best_distance = distance;
            best_anchored = anchored;
          }
        }
      }
    }
  }
  return best;
}

}  // namespace fvv
