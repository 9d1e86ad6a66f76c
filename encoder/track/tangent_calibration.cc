#include "encoder/track/tangent_calibration.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "encoder/capture/calibration.h"

namespace fvv {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct Tangent {
  Eigen::Vector2d point;
  bool border = false;
};

// The points where the two lines through the epipole `e` (homogeneous,
// normalised coordinates) touch the hull, the lowest angle first. False when
// the epipole sees the hull over a wider angle than `max_cone` (radians), or
// lies inside it.
bool TangentPoints(const OutlineHull& hull, const Eigen::Vector3d& e, double max_cone,
                   Tangent out[2]) {
  if (hull.points.size() < 3) return false;
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& p : hull.points) centre += p;
  centre /= double(hull.points.size());
  // An epipole at infinity (the other camera beside this one, in its image
  // plane) is taken far away along its direction: the lines are then parallel.
  const double far = 1e9 * std::max(1.0, e.head<2>().norm());
  const double z = std::abs(e.z()) * far < e.head<2>().norm()
                       ? (e.z() < 0 ? -1 : 1) * e.head<2>().norm() / far
                       : e.z();
  if (z == 0) return false;
  const Eigen::Vector2d epipole = e.head<2>() / z;
  // Every line through a point inside the hull crosses it (behind the camera
  // as well: the lines are the same).
  if (InsideOutlineHull(hull, epipole)) return false;
  const Eigen::Vector2d ref = centre - epipole;
  double lo = 1e9, hi = -1e9;
  size_t ilo = 0, ihi = 0;
  for (size_t i = 0; i < hull.points.size(); ++i) {
    const Eigen::Vector2d v = hull.points[i] - epipole;
    const double a = std::atan2(ref.x() * v.y() - ref.y() * v.x(), ref.dot(v));
    if (a < lo) lo = a, ilo = i;
    if (a > hi) hi = a, ihi = i;
  }
  if (hi - lo > max_cone) return false;
  out[0] = {hull.points[ilo], hull.at_border[ilo] != 0};
  out[1] = {hull.points[ihi], hull.at_border[ihi] != 0};
  return true;
}

Eigen::Matrix3d Skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d s;
  s << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return s;
}

// One residual: a tangent point's signed distance (pixels) from the epipolar
// line of the other camera's matching tangent point, in `camera`'s image.
struct Residual {
  uint32_t camera;
  double value;
};

// Every tangent residual of the cameras with the orientations given.
class TangentProblem {
 public:
  TangentProblem(const std::vector<Camera>& cameras,
                 const std::vector<std::vector<OutlineHull>>& outlines, double max_cone)
      : cameras_(cameras), outlines_(outlines), max_cone_(max_cone) {
    for (const Camera& c : cameras) centres_.push_back(CameraCentre(c));
  }

  // Appends the residuals of every frame and pair of cameras; with `layout`
  // given, the slots it lists (NaN where a slot has no tangent now), else the
  // tangents found now, and their slots into `layout_out`.
  void Evaluate(const std::vector<Eigen::Matrix3d>& rotations, const std::vector<size_t>* layout,
                std::vector<Residual>* residuals, std::vector<size_t>* layout_out) const {
    residuals->clear();
    const size_t n = cameras_.size();
    size_t slot = 0, next = 0;
    for (size_t f = 0; f < outlines_.size(); ++f) {
      for (size_t i = 0; i < n; ++i) {
        for (size_t j = i + 1; j < n; ++j, slot += 4) {
          if (layout != nullptr && (next >= layout->size() || (*layout)[next] != slot)) continue;
          double r[4];
          const bool ok = PairResiduals(rotations, outlines_[f], i, j, r);
          for (int k = 0; k < 4; ++k) {
            if (layout != nullptr) {
              residuals->push_back({uint32_t(k % 2 == 0 ? j : i), ok ? r[k] : NAN});
            } else if (ok) {
              residuals->push_back({uint32_t(k % 2 == 0 ? j : i), r[k]});
            }
          }
          if (layout != nullptr) {
            ++next;
          } else if (ok) {
            layout_out->push_back(slot);
          }
        }
      }
    }
  }

 private:
  // The four residuals of cameras i and j in one frame: per matched pair of
  // tangents, the distance in j's image, then in i's. False when either
  // camera has no usable tangent.
  bool PairResiduals(const std::vector<Eigen::Matrix3d>& rot, const std::vector<OutlineHull>& frame,
                     size_t i, size_t j, double r[4]) const {
    if (i >= frame.size() || j >= frame.size()) return false;
    const Eigen::Vector3d b = centres_[j] - centres_[i];
    Tangent ti[2], tj[2];
    if (!TangentPoints(frame[i], rot[i] * b, max_cone_, ti) ||
        !TangentPoints(frame[j], -(rot[j] * b), max_cone_, tj)) {
      return false;
    }
    // Match the tangents by the plane through both centres each lies in.
    Eigen::Vector3d u = b.unitOrthogonal(), v = b.normalized().cross(u);
    auto plane_angle = [&](const Eigen::Matrix3d& turn, const Eigen::Vector2d& p) {
      const Eigen::Vector3d n = b.cross(turn.transpose() * p.homogeneous());
      return std::atan2(n.dot(v), n.dot(u));
    };
    auto apart = [](double a, double c) {
      const double d = std::fmod(std::abs(a - c), 2 * kPi);
      return std::min(d, 2 * kPi - d);
    };
    const double ai0 = plane_angle(rot[i], ti[0].point), ai1 = plane_angle(rot[i], ti[1].point);
    const double aj0 = plane_angle(rot[j], tj[0].point), aj1 = plane_angle(rot[j], tj[1].point);
    const bool straight = apart(ai0, aj0) + apart(ai1, aj1) <= apart(ai0, aj1) + apart(ai1, aj0);
    const Tangent* match[2][2] = {{&ti[0], straight ? &tj[0] : &tj[1]},
                                  {&ti[1], straight ? &tj[1] : &tj[0]}};
    const Eigen::Matrix3d e = rot[j] * Skew(b) * rot[i].transpose();
    for (int m = 0; m < 2; ++m) {
      if (match[m][0]->border || match[m][1]->border) return false;
      const Eigen::Vector3d xi = match[m][0]->point.homogeneous(),
                            xj = match[m][1]->point.homogeneous();
      const double s = xj.dot(e * xi);
      const Eigen::Vector3d lj = e * xi, li = e.transpose() * xj;
      const double nj = lj.head<2>().norm(), ni = li.head<2>().norm();
      if (nj < 1e-12 || ni < 1e-12) return false;
      r[2 * m] = s / nj * cameras_[j].fx;
      r[2 * m + 1] = s / ni * cameras_[i].fx;
    }
    return true;
  }

  const std::vector<Camera>& cameras_;
  const std::vector<std::vector<OutlineHull>>& outlines_;
  const double max_cone_;
  std::vector<Eigen::Vector3d> centres_;
};

// The parameters: per camera a turn (radians) about its own x and y axes, and
// about its optical axis with roll.
struct Layout {
  size_t cameras;
  int per_camera;  // 2 or 3
  Eigen::Index size() const { return Eigen::Index(cameras) * per_camera; }
  Eigen::Vector3d Turn(const Eigen::VectorXd& x, size_t c) const {
    const Eigen::Index at = Eigen::Index(c) * per_camera;
    return Eigen::Vector3d(x[at], x[at + 1], per_camera == 3 ? x[at + 2] : 0.0);
  }
  std::vector<Eigen::Matrix3d> Rotations(const std::vector<Camera>& cams,
                                         const Eigen::VectorXd& x) const {
    std::vector<Eigen::Matrix3d> out;
    for (size_t c = 0; c < cameras; ++c) {
      const Eigen::Vector3d w = Turn(x, c);
      const Eigen::Matrix3d turn =
          w.norm() < 1e-15 ? Eigen::Matrix3d::Identity()
                           : Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
      out.push_back(turn * CameraRotation(cams[c]));
    }
    return out;
  }
};

double Huber(double r, double delta) {
  const double a = std::abs(r);
  return a <= delta ? 0.5 * a * a : delta * (a - 0.5 * delta);
}

std::vector<double> MedianPerCamera(size_t n, const std::vector<Residual>& residuals,
                                    std::vector<uint32_t>* counts) {
  std::vector<std::vector<double>> per(n);
  for (const Residual& r : residuals) {
    if (std::isfinite(r.value)) per[r.camera].push_back(std::abs(r.value));
  }
  std::vector<double> median(n, -1);
  if (counts != nullptr) counts->assign(n, 0);
  for (size_t c = 0; c < n; ++c) {
    if (counts != nullptr) (*counts)[c] = uint32_t(per[c].size());
    if (per[c].empty()) continue;
    std::nth_element(per[c].begin(), per[c].begin() + per[c].size() / 2, per[c].end());
    median[c] = per[c][per[c].size() / 2];
  }
  return median;
}

}  // namespace

std::vector<double> TangentDistances(const std::vector<Camera>& cameras,
                                     const std::vector<std::vector<OutlineHull>>& outlines,
                                     const TangentCalibrationOptions& options,
                                     std::vector<uint32_t>* tangents) {
  const TangentProblem problem(cameras, outlines, options.max_cone_deg * kPi / 180);
  std::vector<Residual> residuals;
  std::vector<size_t> layout;
  std::vector<Eigen::Matrix3d> rotations;
  for (const Camera& c : cameras) rotations.push_back(CameraRotation(c));
  problem.Evaluate(rotations, nullptr, &residuals, &layout);
  return MedianPerCamera(cameras.size(), residuals, tangents);
}

StatusOr<TangentCalibration> RefineCamerasFromTangents(
    const std::vector<Camera>& cameras, const std::vector<std::vector<OutlineHull>>& outlines,
    const TangentCalibrationOptions& o) {
  const size_t n = cameras.size();
  if (n < 2) return InvalidArgument("refine-calib: tangents need 2 cameras or more");
  if (!(o.huber_px > 0) || !(o.prior_px > 0) || o.iterations < 1) {
    return InvalidArgument("refine-calib: the tangent refinement's options must be positive");
  }
  const TangentProblem problem(cameras, outlines, o.max_cone_deg * kPi / 180);
  const Layout lay{n, o.roll ? 3 : 2};
  const Eigen::Index dims = lay.size();
  Eigen::VectorXd x = Eigen::VectorXd::Zero(dims);
  TangentCalibration result;
  std::vector<Residual> residuals;
  std::vector<size_t> layout;
  problem.Evaluate(lay.Rotations(cameras, x), nullptr, &residuals, &layout);
  result.before_px = MedianPerCamera(n, residuals, &result.tangents);
  if (residuals.size() < 20) {
    return InvalidArgument("refine-calib: " + std::to_string(residuals.size()) +
                           " tangent points, too few to refine on (at least 20): the cameras "
                           "see the actor in too few frames together, or his silhouettes run "
                           "off the images");
  }
  // The prior's weight per parameter: a turn of prior_px pixels is one unit.
  Eigen::VectorXd prior_scale(dims);
  for (size_t c = 0; c < n; ++c) {
    prior_scale.segment(Eigen::Index(lay.per_camera) * Eigen::Index(c), lay.per_camera)
        .setConstant(cameras[c].fx / o.prior_px);
  }
  auto cost = [&](const std::vector<Residual>& r, const Eigen::VectorXd& at) {
    double total = 0;
    for (const Residual& e : r) total += std::isfinite(e.value) ? Huber(e.value, o.huber_px) : 0;
    return total + 0.5 * at.cwiseProduct(prior_scale).squaredNorm();
  };
  double lambda = 1e-3;
  const double h = 1e-6;
  Eigen::MatrixXd basis;  // the directions turned along (columns), set in the first iteration
  for (int it = 0; it < o.iterations; ++it) {
    result.iterations = it + 1;
    layout.clear();
    problem.Evaluate(lay.Rotations(cameras, x), nullptr, &residuals, &layout);
    const Eigen::Index m = Eigen::Index(residuals.size());
    Eigen::VectorXd r(m), w(m);
    for (Eigen::Index k = 0; k < m; ++k) {
      r[k] = residuals[size_t(k)].value;
      w[k] = std::abs(r[k]) <= o.huber_px ? 1.0 : o.huber_px / std::abs(r[k]);
    }
    Eigen::MatrixXd jac(m, dims);
    std::vector<Residual> plus, minus;
    for (Eigen::Index d = 0; d < dims; ++d) {
      Eigen::VectorXd xp = x, xm = x;
      xp[d] += h;
      xm[d] -= h;
      problem.Evaluate(lay.Rotations(cameras, xp), &layout, &plus, nullptr);
      problem.Evaluate(lay.Rotations(cameras, xm), &layout, &minus, nullptr);
      for (Eigen::Index k = 0; k < m; ++k) {
        const double a = plus[size_t(k)].value, c = minus[size_t(k)].value;
        jac(k, d) = std::isfinite(a) && std::isfinite(c) ? (a - c) / (2 * h) : 0;
      }
    }
    const Eigen::MatrixXd a = jac.transpose() * w.asDiagonal() * jac +
                              Eigen::MatrixXd(prior_scale.cwiseAbs2().asDiagonal());
    const Eigen::VectorXd g =
        jac.transpose() * w.cwiseProduct(r) + prior_scale.cwiseAbs2().cwiseProduct(x);
    const double now = cost(residuals, x);
    if (it == 0) {
      // The combinations of turns the tangents measure: the eigenvectors of
      // their information, each turn in pixels (times the focal length).
      Eigen::VectorXd px(dims);
      for (size_t c = 0; c < n; ++c) {
        px.segment(Eigen::Index(lay.per_camera) * Eigen::Index(c), lay.per_camera)
            .setConstant(cameras[c].fx);
      }
      const Eigen::MatrixXd info = px.cwiseInverse().asDiagonal() *
                                   (jac.transpose() * w.asDiagonal() * jac) *
                                   px.cwiseInverse().asDiagonal();
      const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(info);
      const double least = o.min_information * double(m);
      std::vector<Eigen::Index> kept;
      for (Eigen::Index k = 0; k < dims; ++k) {
        if (es.eigenvalues()[k] >= least) kept.push_back(k);
      }
      result.held_directions = int(dims - Eigen::Index(kept.size()));
      basis.resize(dims, Eigen::Index(kept.size()));
      for (size_t k = 0; k < kept.size(); ++k) {
        basis.col(Eigen::Index(k)) =
            px.cwiseInverse().asDiagonal() * es.eigenvectors().col(kept[k]);
      }
    }
    const Eigen::MatrixXd az = basis.transpose() * a * basis;
    const Eigen::VectorXd gz = basis.transpose() * g;
    bool moved = false;
    Eigen::VectorXd step;
    for (int tries = 0; tries < 10 && !moved; ++tries) {
      Eigen::MatrixXd damped = az;
      damped.diagonal() *= 1 + lambda;
      step = basis * damped.ldlt().solve(-gz);
      std::vector<Residual> trial;
      problem.Evaluate(lay.Rotations(cameras, x + step), &layout, &trial, nullptr);
      if (cost(trial, x + step) < now) {
        x += step;
        lambda = std::max(lambda / 3, 1e-9);
        moved = true;
      } else {
        lambda *= 4;
      }
    }
    // Stop when no camera's image moves by a thousandth of a pixel.
    double largest = 0;
    for (size_t c = 0; c < n; ++c) {
      largest = std::max(largest, lay.Turn(step, c).norm() * cameras[c].fx);
    }
    if (!moved || largest < 1e-3) break;
  }
  const std::vector<Eigen::Matrix3d> rotations = lay.Rotations(cameras, x);
  for (size_t c = 0; c < n; ++c) {
    Camera k = cameras[c];
    const Eigen::Vector3d t = -rotations[c] * CameraCentre(cameras[c]);
    for (int e = 0; e < 9; ++e) k.rotation[size_t(e)] = rotations[c](e / 3, e % 3);
    for (int e = 0; e < 3; ++e) k.translation[size_t(e)] = t[e];
    result.cameras.push_back(k);
    result.turn_deg.push_back(lay.Turn(x, c).norm() * 180 / kPi);
    if (result.turn_deg[c] > o.max_turn_deg) {
      char turn[96];
      std::snprintf(turn, sizeof(turn), " would turn %.2f degrees (more than %.2f)",
                    result.turn_deg[c], o.max_turn_deg);
      return InvalidArgument("refine-calib: camera " + k.name + turn +
                             ": the calibration is wrong in another way than a bumped camera "
                             "(another take's file, a unit, an axis), or the masks are (fvv "
                             "capture sheet --persons)");
    }
  }
  layout.clear();
  problem.Evaluate(rotations, nullptr, &residuals, &layout);
  result.after_px = MedianPerCamera(n, residuals, nullptr);
  for (const Residual& e : residuals) result.mean_cost += Huber(e.value, o.huber_px);
  result.mean_cost /= double(std::max<size_t>(1, residuals.size()));
  return result;
}

}  // namespace fvv
