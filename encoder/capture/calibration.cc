#include "encoder/capture/calibration.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace fvv {

Eigen::Matrix3d CameraRotation(const Camera& camera) {
  Eigen::Matrix3d r;
  for (int i = 0; i < 9; ++i) r(i / 3, i % 3) = camera.rotation[i];
  return r;
}

Eigen::Vector3d CameraTranslation(const Camera& camera) {
  return Eigen::Vector3d(camera.translation[0], camera.translation[1], camera.translation[2]);
}

Eigen::Vector3d CameraCentre(const Camera& camera) {
  return -CameraRotation(camera).transpose() * CameraTranslation(camera);
}

Eigen::Vector2d Distort(const Camera& c, const Eigen::Vector2d& n) {
  const double k1 = c.distortion[0], k2 = c.distortion[1], p1 = c.distortion[2],
               p2 = c.distortion[3], k3 = c.distortion[4];
  const double x = n.x(), y = n.y(), r2 = x * x + y * y;
  const double radial = 1 + r2 * (k1 + r2 * (k2 + r2 * k3));
  return {x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x),
          y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y};
}

Eigen::Vector2d Undistort(const Camera& c, const Eigen::Vector2d& d) {
  // Newton's method on Distort(n) = d with a numerical Jacobian; a handful of
  // iterations reach 1e-12 for realistic lenses.
  Eigen::Vector2d n = d;
  for (int it = 0; it < 30; ++it) {
    const Eigen::Vector2d r = Distort(c, n) - d;
    if (r.squaredNorm() < 1e-24) break;
    constexpr double h = 1e-7;
    Eigen::Matrix2d j;
    j.col(0) =
        (Distort(c, n + Eigen::Vector2d(h, 0)) - Distort(c, n - Eigen::Vector2d(h, 0))) / (2 * h);
    j.col(1) =
        (Distort(c, n + Eigen::Vector2d(0, h)) - Distort(c, n - Eigen::Vector2d(0, h))) / (2 * h);
    n -= j.inverse() * r;
  }
  return n;
}

bool ProjectPoint(const Camera& camera, const Eigen::Vector3d& world, Eigen::Vector2d* pixel,
                  double* depth) {
  const Eigen::Vector3d p = CameraRotation(camera) * world + CameraTranslation(camera);
  if (depth) *depth = p.z();
  if (p.z() <= 1e-9) return false;
  const Eigen::Vector2d d = Distort(camera, Eigen::Vector2d(p.x() / p.z(), p.y() / p.z()));
  *pixel = Eigen::Vector2d(camera.fx * d.x() + camera.cx, camera.fy * d.y() + camera.cy);
  return true;
}

Eigen::Vector3d UnprojectPixel(const Camera& camera, const Eigen::Vector2d& pixel, double depth) {
  const Eigen::Vector2d d((pixel.x() - camera.cx) / camera.fx, (pixel.y() - camera.cy) / camera.fy);
  const Eigen::Vector2d n = Undistort(camera, d);
  const Eigen::Vector3d p(n.x() * depth, n.y() * depth, depth);
  return CameraRotation(camera).transpose() * (p - CameraTranslation(camera));
}

Status ValidateCalibration(const Camera& c, const std::string& what) {
  auto bad = [&](const std::string& m) { return InvalidArgument(what + ": " + m); };
  if (c.width == 0 || c.height == 0 || c.width > 16384 || c.height > 16384) {
    return bad("image size " + std::to_string(c.width) + "x" + std::to_string(c.height) +
               " is outside 1..16384");
  }
  for (double v : {c.fx, c.fy, c.cx, c.cy}) {
    if (!std::isfinite(v)) return bad("K has a non-finite entry");
  }
  if (c.fx <= 0 || c.fy <= 0) return bad("focal lengths in K must be positive");
  if (c.cx < -0.5 * c.width || c.cx > 1.5 * c.width || c.cy < -0.5 * c.height ||
      c.cy > 1.5 * c.height) {
    return bad("principal point (" + std::to_string(c.cx) + ", " + std::to_string(c.cy) +
               ") lies far outside the image");
  }
  for (double v : c.distortion) {
    if (!std::isfinite(v) || std::abs(v) > 10) return bad("distortion coefficient out of range");
  }
  for (double v : c.rotation) {
    if (!std::isfinite(v)) return bad("R has a non-finite entry");
  }
  for (double v : c.translation) {
    if (!std::isfinite(v) || std::abs(v) > 1e4) return bad("t is not finite or beyond 10 km");
  }
  const Eigen::Matrix3d r = CameraRotation(c);
  const double ortho = (r * r.transpose() - Eigen::Matrix3d::Identity()).norm();
  if (ortho > 1e-4)
    return bad("R is not orthonormal (|R R^T - I| = " + std::to_string(ortho) + ")");
  if (r.determinant() < 0) return bad("R is a reflection (determinant -1), not a rotation");
  // Distortion must stay monotonic out to the image corners, or undistortion is ambiguous.
  const double corner_x = std::max(c.cx, c.width - c.cx) / c.fx;
  const double corner_y = std::max(c.cy, c.height - c.cy) / c.fy;
  double last = 0;
  for (int i = 1; i <= 64; ++i) {
    const double s = i / 64.0;
    const double rad = Distort(c, Eigen::Vector2d(s * corner_x, s * corner_y)).norm();
    if (rad <= last) return bad("distortion folds over inside the image (not monotonic)");
    last = rad;
  }
  return Status::Ok();
}

int ReductionFactor(const Camera& camera, int max_side) {
  return std::max(1, int(std::ceil(double(std::max(camera.width, camera.height)) / max_side)));
}

Camera ReducedCamera(const Camera& full, int factor) {
  Camera c = full;
  c.width = full.width / uint32_t(factor);
  c.height = full.height / uint32_t(factor);
  // Reduced pixel k covers full pixels k*f .. k*f + f - 1, whose centre is
  // k*f + (f - 1) / 2.
  const double f = factor;
  c.fx = full.fx / f;
  c.fy = full.fy / f;
  c.cx = (full.cx - (f - 1) / 2) / f;
  c.cy = (full.cy - (f - 1) / 2) / f;
  return c;
}

Camera LookAtCamera(const std::string& name, uint32_t width, uint32_t height, double focal_px,
                    const Eigen::Vector3d& centre, const Eigen::Vector3d& target,
                    const Eigen::Vector3d& up) {
  Camera c;
  c.name = name;
  c.width = width;
  c.height = height;
  c.fx = c.fy = focal_px;
  c.cx = (width - 1) / 2.0;
  c.cy = (height - 1) / 2.0;
  const Eigen::Vector3d f = (target - centre).normalized();          // camera +z
  Eigen::Vector3d side = f.cross(up);                                // camera +x (image right)
  if (side.norm() < 1e-9) side = f.cross(Eigen::Vector3d::UnitX());  // looking straight down
  side.normalize();
  const Eigen::Vector3d down = f.cross(side);  // camera +y (image down)
  Eigen::Matrix3d r;
  r.row(0) = side;
  r.row(1) = down;
  r.row(2) = f;
  const Eigen::Vector3d t = -r * centre;
  for (int i = 0; i < 9; ++i) c.rotation[i] = r(i / 3, i % 3);
  for (int i = 0; i < 3; ++i) c.translation[i] = t[i];
  return c;
}

}  // namespace fvv
