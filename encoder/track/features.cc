#include "encoder/track/features.h"

#include <Eigen/Dense>
#include <cmath>
#include <nlohmann/json.hpp>
#include <optional>

#include "encoder/body/generic_body.h"
#include "encoder/capture/calibration.h"
#include "encoder/io/image_io.h"

namespace fvv {

bool IsFeatureName(const std::string& name) {
  for (int j = 0; j < kGenericJointCount; ++j) {
    if (name == GenericJointName(j)) return true;
  }
  return false;
}

StatusOr<FeatureSet> ParseFeatures(const std::string& text, const std::vector<Camera>& cameras,
                                   uint32_t frame_count, const std::string& what) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    return Corrupt(what + ": not JSON (" + e.what() + ")");
  }
  if (!j.is_object() || !j.contains("features") || !j["features"].is_array()) {
    return Corrupt(what + R"(: expected {"features": [{"frame", "camera", "points"}, ...]})");
  }
  std::map<std::string, uint32_t> camera_index;
  for (uint32_t c = 0; c < cameras.size(); ++c) camera_index[cameras[c].name] = c;
  FeatureSet set;
  for (size_t i = 0; i < j["features"].size(); ++i) {
    const nlohmann::json& e = j["features"][i];
    const std::string where = what + ": features[" + std::to_string(i) + "]";
    if (!e.is_object() || !e.contains("frame") || !e["frame"].is_number_unsigned() ||
        !e.contains("camera") || !e["camera"].is_string() || !e.contains("points") ||
        !e["points"].is_object()) {
      return Corrupt(where + R"(: needs "frame" (integer), "camera" (name), "points" (object))");
    }
    const uint64_t frame = e["frame"].get<uint64_t>();
    if (frame >= frame_count) {
      return InvalidArgument(where + ": frame " + std::to_string(frame) + " beyond the capture's " +
                             std::to_string(frame_count));
    }
    const std::string camera = e["camera"].get<std::string>();
    const auto cam = camera_index.find(camera);
    if (cam == camera_index.end()) {
      return InvalidArgument(where + ": no camera \"" + camera + "\" in the capture");
    }
    const Camera& calib = cameras[cam->second];
    for (const auto& [name, xy] : e["points"].items()) {
      if (!IsFeatureName(name)) {
        return InvalidArgument(where + ": \"" + name +
                               "\" is not a feature name (the generic body's joints: root, "
                               "l_hip, l_knee, l_ankle, l_shoulder, l_elbow, l_wrist, r_..., "
                               "lumbar, thoracic, neck, head)");
      }
      if (!xy.is_array() || xy.size() != 2 || !xy[0].is_number() || !xy[1].is_number()) {
        return Corrupt(where + "." + name + ": expected [x, y] in pixels");
      }
      const Eigen::Vector2d p(xy[0].get<double>(), xy[1].get<double>());
      if (!(p.x() >= -0.5 && p.y() >= -0.5 && p.x() <= calib.width - 0.5 &&
            p.y() <= calib.height - 0.5)) {
        return InvalidArgument(where + "." + name + ": pixel outside camera " + camera + "'s " +
                               std::to_string(calib.width) + "x" + std::to_string(calib.height) +
                               " image");
      }
      set.frames[uint32_t(frame)][name][cam->second] = p;
    }
  }
  return set;
}

StatusOr<FeatureSet> LoadFeatures(const std::string& path, const std::vector<Camera>& cameras,
                                  uint32_t frame_count) {
  StatusOr<std::vector<uint8_t>> bytes = ReadFileBytes(path, 256u << 20);
  if (!bytes.ok()) return bytes.status();
  return ParseFeatures(std::string(bytes->begin(), bytes->end()), cameras, frame_count, path);
}

std::string FeaturesToJson(const FeatureSet& features, const std::vector<Camera>& cameras) {
  nlohmann::json list = nlohmann::json::array();
  for (const auto& [frame, points] : features.frames) {
    std::map<uint32_t, nlohmann::json> per_camera;
    for (const auto& [name, views] : points) {
      for (const auto& [camera, p] : views) per_camera[camera][name] = {p.x(), p.y()};
    }
    for (auto& [camera, pts] : per_camera) {
      list.push_back({{"frame", frame}, {"camera", cameras[camera].name}, {"points", pts}});
    }
  }
  return nlohmann::json{{"features", list}}.dump(1) + "\n";
}

namespace {

// One point from its views: linear, then refined on the reprojection error.
std::optional<Feature3D> Triangulate(const std::map<uint32_t, Eigen::Vector2d>& views,
                                     const std::vector<Camera>& cameras) {
  // Linear: the point nearest all rays, sum |(I - d d^T)(X - C)|^2.
  Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (const auto& [camera, pixel] : views) {
    const Eigen::Vector3d c = CameraCentre(cameras[camera]);
    const Eigen::Vector3d d = (UnprojectPixel(cameras[camera], pixel, 1.0) - c).normalized();
    const Eigen::Matrix3d m = Eigen::Matrix3d::Identity() - d * d.transpose();
    a += m;
    b += m * c;
  }
  Eigen::Vector3d x = a.ldlt().solve(b);
  if (!x.allFinite()) return std::nullopt;
  // Gauss-Newton on the reprojection error (numerical Jacobian).
  const auto residuals = [&](const Eigen::Vector3d& p, Eigen::VectorXd* r) {
    r->resize(2 * Eigen::Index(views.size()));
    Eigen::Index i = 0;
    for (const auto& [camera, pixel] : views) {
      Eigen::Vector2d q;
      if (!ProjectPoint(cameras[camera], p, &q)) return false;
      r->segment<2>(i) = q - pixel;
      i += 2;
    }
    return true;
  };
  Eigen::VectorXd r;
  if (!residuals(x, &r)) return std::nullopt;
  for (int it = 0; it < 5; ++it) {
    Eigen::MatrixXd jac(r.size(), 3);
    bool ok = true;
    for (int k = 0; k < 3 && ok; ++k) {
      Eigen::Vector3d step = Eigen::Vector3d::Zero();
      step[k] = 1e-6;
      Eigen::VectorXd rp, rm;
      ok = residuals(x + step, &rp) && residuals(x - step, &rm);
      if (ok) jac.col(k) = (rp - rm) / 2e-6;
    }
    if (!ok) break;
    const Eigen::Vector3d delta = (jac.transpose() * jac).ldlt().solve(-jac.transpose() * r);
    Eigen::VectorXd next;
    if (!delta.allFinite() || !residuals(x + delta, &next) || next.squaredNorm() > r.squaredNorm())
      break;
    x += delta;
    r = next;
  }
  Feature3D f;
  f.position = x;
  f.views = int(views.size());
  f.rms_px = std::sqrt(r.squaredNorm() / double(views.size()));
  return f;
}

}  // namespace

std::map<std::string, Feature3D> TriangulateFeatures(
    const std::map<std::string, std::map<uint32_t, Eigen::Vector2d>>& points,
    const std::vector<Camera>& cameras, double max_rms_px) {
  std::map<std::string, Feature3D> out;
  for (const auto& [name, views] : points) {
    if (views.size() < 2) continue;
    std::optional<Feature3D> f = Triangulate(views, cameras);
    if (f && f->rms_px <= max_rms_px) {
      out[name] = *f;
      continue;
    }
    // One wrong view (a mislabelled point, another person's joint) spoils the
    // rest: with three or more, each is left out in turn and the subset that
    // agrees best kept.
    if (views.size() < 3) continue;
    for (const auto& [camera, pixel] : views) {
      std::map<uint32_t, Eigen::Vector2d> rest = views;
      rest.erase(camera);
      std::optional<Feature3D> g = Triangulate(rest, cameras);
      if (g && g->rms_px <= max_rms_px && (!out.count(name) || g->rms_px < out[name].rms_px)) {
        out[name] = *g;
      }
    }
  }
  return out;
}

}  // namespace fvv
