#include "encoder/track/calibration_refinement.h"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <map>
#include <string>

#include "encoder/body/generic_body.h"
#include "encoder/capture/calibration.h"
#include "encoder/track/features.h"

namespace fvv {

namespace {

constexpr double kPi = 3.14159265358979323846;

struct Pose {
  Eigen::Matrix3d rotation;  // world -> camera
  Eigen::Vector3d centre;    // world
};

struct Observation {
  uint32_t camera = 0;
  Eigen::Vector2d pixel;
};

struct Point {
  Eigen::Vector3d position;
  std::vector<Observation> seen;
};

Eigen::Matrix3d Turn(const Eigen::Vector3d& w) {
  const double angle = w.norm();
  if (angle < 1e-15) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, w / angle).toRotationMatrix();
}

// The rotation vector of R (the inverse of Turn).
Eigen::Vector3d RotationVector(const Eigen::Matrix3d& r) {
  const Eigen::AngleAxisd a(r);
  return a.angle() * a.axis();
}

bool Pixel(const Camera& c, const Pose& pose, const Eigen::Vector3d& x, Eigen::Vector2d* pixel) {
  const Eigen::Vector3d p = pose.rotation * (x - pose.centre);
  if (p.z() <= 1e-6) return false;
  const Eigen::Vector2d d = Distort(c, Eigen::Vector2d(p.x() / p.z(), p.y() / p.z()));
  *pixel = Eigen::Vector2d(c.fx * d.x() + c.cx, c.fy * d.y() + c.cy);
  return true;
}

Camera WithPose(Camera c, const Pose& pose) {
  for (int i = 0; i < 9; ++i) c.rotation[size_t(i)] = pose.rotation(i / 3, i % 3);
  const Eigen::Vector3d t = -pose.rotation * pose.centre;
  for (int i = 0; i < 3; ++i) c.translation[size_t(i)] = t[i];
  return c;
}

// Per frame, the confident sightings as TriangulateFeatures takes them.
std::map<std::string, std::map<uint32_t, Eigen::Vector2d>> FramePoints(
    const std::vector<std::vector<JointSighting>>& frame, double min_confidence) {
  std::map<std::string, std::map<uint32_t, Eigen::Vector2d>> points;
  for (uint32_t c = 0; c < frame.size(); ++c) {
    for (const JointSighting& s : frame[c]) {
      if (s.confidence >= min_confidence) points[GenericJointName(s.joint)][c] = s.pixel;
    }
  }
  return points;
}

// Per camera, the median distance of its confident sightings from the joints
// triangulated by all cameras; how many sightings that was in `counted`.
std::vector<double> MedianReprojection(
    const std::vector<Camera>& cameras,
    const std::vector<std::vector<std::vector<JointSighting>>>& sightings,
    const CalibrationRefinementOptions& o, std::vector<uint32_t>* counted = nullptr) {
  std::vector<std::vector<double>> d(cameras.size());
  for (const auto& frame : sightings) {
    const auto points = FramePoints(frame, o.min_confidence);
    const auto world = TriangulateFeatures(points, cameras, o.tolerance_px);
    for (const auto& [name, views] : points) {
      auto it = world.find(name);
      if (it == world.end()) continue;
      for (const auto& [c, pixel] : views) {
        Eigen::Vector2d p;
        if (ProjectPoint(cameras[c], it->second.position, &p)) d[c].push_back((p - pixel).norm());
      }
    }
  }
  std::vector<double> median(cameras.size(), -1);
  if (counted) counted->assign(cameras.size(), 0);
  for (size_t c = 0; c < cameras.size(); ++c) {
    if (counted) (*counted)[c] = uint32_t(d[c].size());
    if (d[c].empty()) continue;
    std::nth_element(d[c].begin(), d[c].begin() + d[c].size() / 2, d[c].end());
    median[c] = d[c][d[c].size() / 2];
  }
  return median;
}

// The bundle adjustment itself: poses and points in place.
class Adjustment {
 public:
  Adjustment(const std::vector<Camera>& cameras, std::vector<Pose>* poses,
             std::vector<Point>* points, const CalibrationRefinementOptions& o)
      : cameras_(cameras), poses_(*poses), points_(*points), o_(o) {
    for (const Camera& c : cameras) {
      initial_.push_back({CameraRotation(c), CameraCentre(c)});
    }
  }

  // Residual scale (pixels) for the Huber weights: the robust spread of the
  // errors as they are; sightings beyond `cap` scales are dropped.
  void SetScale(double scale, double cap) {
    scale_ = std::max(scale, 0.5);
    for (Point& p : points_) {
      std::vector<Observation> kept;
      for (const Observation& ob : p.seen) {
        Eigen::Vector2d px;
        if (Pixel(cameras_[ob.camera], poses_[ob.camera], p.position, &px) &&
            (px - ob.pixel).norm() <= cap * scale_) {
          kept.push_back(ob);
        }
      }
      p.seen = kept;
    }
    points_.erase(std::remove_if(points_.begin(), points_.end(),
                                 [](const Point& p) { return p.seen.size() < 2; }),
                  points_.end());
  }

  double Cost(const std::vector<Pose>& poses, const std::vector<Point>& points) const {
    double cost = 0;
    for (const Point& p : points) {
      for (const Observation& ob : p.seen) {
        Eigen::Vector2d px;
        if (!Pixel(cameras_[ob.camera], poses[ob.camera], p.position, &px)) {
          cost += 1e6;
          continue;
        }
        const double e = (px - ob.pixel).norm() / scale_;
        cost += e <= kHuber ? e * e : 2 * kHuber * e - kHuber * kHuber;
      }
    }
    for (size_t c = 0; c < poses.size(); ++c) cost += PriorResidual(poses[c], c).squaredNorm();
    return cost;
  }

  // Levenberg-Marquardt; returns the iterations taken.
  int Run(int iterations) {
    const size_t n = poses_.size();
    double lambda = 1e-3, cost = Cost(poses_, points_);
    int it = 0;
    for (; it < iterations; ++it) {
      // Normal equations: camera blocks U, point blocks V, cross blocks W.
      Eigen::MatrixXd u = Eigen::MatrixXd::Zero(6 * n, 6 * n);
      Eigen::VectorXd gc = Eigen::VectorXd::Zero(6 * n);
      std::vector<Eigen::Matrix3d> v(points_.size(), Eigen::Matrix3d::Zero());
      std::vector<Eigen::Vector3d> gp(points_.size(), Eigen::Vector3d::Zero());
      std::vector<std::map<uint32_t, Eigen::Matrix<double, 6, 3>>> w(points_.size());
      for (size_t i = 0; i < points_.size(); ++i) {
        const Point& p = points_[i];
        for (const Observation& ob : p.seen) {
          Eigen::Matrix<double, 2, 6> jc;
          Eigen::Matrix<double, 2, 3> jp;
          Eigen::Vector2d r;
          if (!Linearise(ob, p.position, &r, &jc, &jp)) continue;
          const double e = r.norm(), weight = (e <= kHuber ? 1.0 : kHuber / e);
          const size_t k = ob.camera;
          u.block<6, 6>(6 * k, 6 * k) += weight * jc.transpose() * jc;
          gc.segment<6>(6 * k) += weight * jc.transpose() * r;
          v[i] += weight * jp.transpose() * jp;
          gp[i] += weight * jp.transpose() * r;
          auto [slot, fresh] = w[i].try_emplace(ob.camera, Eigen::Matrix<double, 6, 3>::Zero());
          slot->second += weight * jc.transpose() * jp;
        }
      }
      for (size_t c = 0; c < n; ++c) {
        // The prior's Jacobian is diagonal to first order.
        const Eigen::Matrix<double, 6, 1> r = PriorResidual(poses_[c], c);
        const Eigen::Matrix<double, 6, 1> j = PriorScale();
        u.block<6, 6>(6 * c, 6 * c) += Eigen::Matrix<double, 6, 6>(j.cwiseAbs2().asDiagonal());
        gc.segment<6>(6 * c) += j.cwiseProduct(r);
      }
      bool improved = false;
      while (!improved && lambda < 1e8) {
        // Eliminate the points (Schur complement), solve for the cameras,
        // then back-substitute.
        Eigen::MatrixXd s = u;
        s.diagonal() *= 1 + lambda;
        Eigen::VectorXd rhs = -gc;
        std::vector<Eigen::Matrix3d> v_inv(points_.size());
        for (size_t i = 0; i < points_.size(); ++i) {
          Eigen::Matrix3d vi = v[i];
          vi.diagonal() *= 1 + lambda;
          vi.diagonal().array() += 1e-12;
          v_inv[i] = vi.inverse();
          for (const auto& [a, wa] : w[i]) {
            const Eigen::Matrix<double, 6, 3> wv = wa * v_inv[i];
            rhs.segment<6>(6 * a) += wv * gp[i];
            for (const auto& [b, wb] : w[i]) {
              s.block<6, 6>(6 * a, 6 * b) -= wv * wb.transpose();
            }
          }
        }
        const Eigen::VectorXd dc = s.ldlt().solve(rhs);
        std::vector<Pose> poses = poses_;
        for (size_t c = 0; c < n; ++c) {
          poses[c].rotation = Turn(dc.segment<3>(6 * c)) * poses_[c].rotation;
          poses[c].centre += dc.segment<3>(6 * c + 3);
        }
        std::vector<Point> points = points_;
        for (size_t i = 0; i < points_.size(); ++i) {
          Eigen::Vector3d b = -gp[i];
          for (const auto& [a, wa] : w[i]) b -= wa.transpose() * dc.segment<6>(6 * a);
          points[i].position += v_inv[i] * b;
        }
        const double trial = Cost(poses, points);
        if (std::isfinite(trial) && trial < cost) {
          const double gain = cost - trial;
          poses_ = poses, points_ = points, cost = trial, improved = true;
          lambda = std::max(lambda / 10, 1e-9);
          if (gain < 1e-9 * cost) return it + 1;
        } else {
          lambda *= 10;
        }
      }
      if (!improved) break;
    }
    return it;
  }

 private:
  static constexpr double kHuber = 2.0;  // in residual scales

  Eigen::Matrix<double, 6, 1> PriorScale() const {
    Eigen::Matrix<double, 6, 1> s;
    s << Eigen::Vector3d::Constant(180 / (kPi * o_.prior_rotation_deg)),
        Eigen::Vector3d::Constant(1 / o_.prior_centre_m);
    return s;
  }
  Eigen::Matrix<double, 6, 1> PriorResidual(const Pose& pose, size_t c) const {
    Eigen::Matrix<double, 6, 1> r;
    r << RotationVector(pose.rotation * initial_[c].rotation.transpose()),
        pose.centre - initial_[c].centre;
    return r.cwiseProduct(PriorScale());
  }

  // The scaled residual of one sighting and its derivatives by the camera's
  // turn and shift and by the point (central differences).
  bool Linearise(const Observation& ob, const Eigen::Vector3d& x, Eigen::Vector2d* r,
                 Eigen::Matrix<double, 2, 6>* jc, Eigen::Matrix<double, 2, 3>* jp) const {
    const Camera& c = cameras_[ob.camera];
    const Pose& pose = poses_[ob.camera];
    Eigen::Vector2d px;
    if (!Pixel(c, pose, x, &px)) return false;
    *r = (px - ob.pixel) / scale_;
    constexpr double h = 1e-6;
    for (int j = 0; j < 9; ++j) {
      Eigen::Vector2d plus, minus;
      Pose a = pose, b = pose;
      Eigen::Vector3d xa = x, xb = x;
      if (j < 3) {
        a.rotation = Turn(Eigen::Vector3d::Unit(j) * h) * pose.rotation;
        b.rotation = Turn(Eigen::Vector3d::Unit(j) * -h) * pose.rotation;
      } else if (j < 6) {
        a.centre[j - 3] += h, b.centre[j - 3] -= h;
      } else {
        xa[j - 6] += h, xb[j - 6] -= h;
      }
      if (!Pixel(c, a, xa, &plus) || !Pixel(c, b, xb, &minus)) return false;
      const Eigen::Vector2d d = (plus - minus) / (2 * h * scale_);
      if (j < 6) {
        jc->col(j) = d;
      } else {
        jp->col(j - 6) = d;
      }
    }
    return true;
  }

  const std::vector<Camera>& cameras_;
  std::vector<Pose>& poses_;
  std::vector<Point>& points_;
  const CalibrationRefinementOptions& o_;
  std::vector<Pose> initial_;
  double scale_ = 1;
};

// The robust spread of the sightings' errors: the median distance over
// 1.1774 (a 2D normal's median radius in standard deviations).
double ResidualScale(const std::vector<Camera>& cameras, const std::vector<Pose>& poses,
                     const std::vector<Point>& points) {
  std::vector<double> d;
  for (const Point& p : points) {
    for (const Observation& ob : p.seen) {
      Eigen::Vector2d px;
      if (Pixel(cameras[ob.camera], poses[ob.camera], p.position, &px)) {
        d.push_back((px - ob.pixel).norm());
      }
    }
  }
  if (d.empty()) return 1;
  std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
  return d[d.size() / 2] / 1.1774;
}

}  // namespace

StatusOr<CalibrationRefinement> RefineCameraPoses(
    const std::vector<Camera>& cameras,
    const std::vector<std::vector<std::vector<JointSighting>>>& sightings,
    const CalibrationRefinementOptions& o) {
  const size_t n = cameras.size();
  if (n < 2) return InvalidArgument("refining the calibration needs two cameras or more");
  if (!(o.prior_rotation_deg > 0) || !(o.prior_centre_m > 0) || o.iterations < 1) {
    return InvalidArgument("calibration refinement: the prior and iterations must be positive");
  }
  for (const auto& frame : sightings) {
    if (frame.size() != n) {
      return InvalidArgument("calibration refinement: sightings of " +
                             std::to_string(frame.size()) + " cameras for " + std::to_string(n));
    }
  }
  // The points: each frame's joints triangulated from the views that agree,
  // observed by every camera that saw them.
  std::vector<Point> points;
  for (const auto& frame : sightings) {
    const auto views = FramePoints(frame, o.min_confidence);
    const auto world = TriangulateFeatures(views, cameras, o.tolerance_px);
    for (const auto& [name, seen] : views) {
      auto it = world.find(name);
      if (it == world.end() || seen.size() < 2) continue;
      Point p;
      p.position = it->second.position;
      for (const auto& [c, pixel] : seen) p.seen.push_back({c, pixel});
      points.push_back(std::move(p));
    }
  }
  if (points.size() < 20) {
    return InvalidArgument("calibration refinement: " + std::to_string(points.size()) +
                           " joints seen by two cameras or more; needs 20 (more frames, or a "
                           "person in view of the cameras)");
  }
  std::vector<Pose> poses;
  for (const Camera& c : cameras) poses.push_back({CameraRotation(c), CameraCentre(c)});
  CalibrationRefinement r;
  r.before_px = MedianReprojection(cameras, sightings, o);
  Adjustment adjust(cameras, &poses, &points, o);
  // Twice: the second time with the spread and the outliers of the first's
  // result, no longer of the calibration's error.
  for (int round = 0; round < 2; ++round) {
    adjust.SetScale(ResidualScale(cameras, poses, points), 6.0);
    r.iterations += adjust.Run(o.iterations);
  }
  r.points = uint32_t(points.size());
  for (size_t c = 0; c < n; ++c) {
    r.cameras.push_back(WithPose(cameras[c], poses[c]));
    const Eigen::Matrix3d turn = poses[c].rotation * CameraRotation(cameras[c]).transpose();
    r.rotation_deg.push_back(Eigen::AngleAxisd(turn).angle() * 180 / kPi);
    r.centre_m.push_back((poses[c].centre - CameraCentre(cameras[c])).norm());
  }
  r.after_px = MedianReprojection(r.cameras, sightings, o, &r.sightings);
  return r;
}

}  // namespace fvv
