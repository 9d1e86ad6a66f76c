#include "encoder/capture/calibration_import.h"

#include <toml++/toml.h>
#include <yaml-cpp/yaml.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdlib>
#include <nlohmann/json.hpp>

#include "encoder/capture/calibration.h"
#include "encoder/io/image_io.h"

namespace fvv {
namespace {

using nlohmann::json;

json FromYaml(const YAML::Node& n) {
  switch (n.Type()) {
    case YAML::NodeType::Sequence: {
      json a = json::array();
      for (const YAML::Node& e : n) a.push_back(FromYaml(e));
      return a;
    }
    case YAML::NodeType::Map: {
      json o = json::object();
      for (const auto& kv : n) o[kv.first.as<std::string>()] = FromYaml(kv.second);
      return o;
    }
    case YAML::NodeType::Scalar: {
      const std::string s = n.Scalar();
      char* end = nullptr;
      const double v = std::strtod(s.c_str(), &end);
      if (!s.empty() && end == s.c_str() + s.size()) return v;
      return s;
    }
    default:
      return nullptr;
  }
}

json FromToml(const toml::node& n) {
  if (const toml::table* t = n.as_table()) {
    json o = json::object();
    for (const auto& [key, value] : *t) o[std::string(key.str())] = FromToml(value);
    return o;
  }
  if (const toml::array* a = n.as_array()) {
    json out = json::array();
    for (const toml::node& e : *a) out.push_back(FromToml(e));
    return out;
  }
  if (auto v = n.value<double>()) return *v;
  if (auto s = n.value<std::string>()) return *s;
  if (auto b = n.value<bool>()) return *b;
  return nullptr;
}

const json* Find(const json& cam, std::initializer_list<const char*> keys) {
  for (const char* k : keys) {
    auto it = cam.find(k);
    if (it != cam.end()) return &*it;
  }
  return nullptr;
}

// Numbers of a matrix in row-major order: opencv-matrix maps, nested or flat lists.
Status Numbers(const json& v, const std::string& what, std::vector<double>* out) {
  out->clear();
  const json* data = &v;
  if (v.is_object()) {
    if (!v.contains("data")) return InvalidArgument(what + ": a matrix map needs \"data\"");
    data = &v["data"];
  }
  if (!data->is_array()) return InvalidArgument(what + ": expected a list of numbers");
  for (const json& e : *data) {
    if (e.is_array()) {
      for (const json& x : e) {
        if (!x.is_number()) return InvalidArgument(what + ": non-numeric entry");
        out->push_back(x.get<double>());
      }
    } else if (e.is_number()) {
      out->push_back(e.get<double>());
    } else {
      return InvalidArgument(what + ": non-numeric entry");
    }
  }
  return Status::Ok();
}

StatusOr<Camera> CameraFrom(const json& c, const std::string& name, double unit,
                            const std::string& where) {
  Camera cam;
  cam.name = name;
  std::vector<double> v;
  const json* k = Find(c, {"K", "camera_matrix", "cameraMatrix", "intrinsics", "intrinsic"});
  if (!k) return InvalidArgument(where + ": no camera matrix (K / camera_matrix)");
  FVV_RETURN_IF_ERROR(Numbers(*k, where + ": K", &v));
  if (v.size() != 9) return InvalidArgument(where + ": K must have 9 entries");
  cam.fx = v[0], cam.cx = v[2], cam.fy = v[4], cam.cy = v[5];
  if (const json* d = Find(
          c, {"D", "dist", "distortion", "dist_coeffs", "distortion_coefficients", "distCoeffs"})) {
    FVV_RETURN_IF_ERROR(Numbers(*d, where + ": distortion", &v));
    if (v.size() > 5) {
      // Rational and thin-prism terms beyond k3 must be zero: fvv models k1 k2 p1 p2 k3.
      for (size_t i = 5; i < v.size(); ++i) {
        if (v[i] != 0) return Unsupported(where + ": distortion terms beyond k3 are not supported");
      }
      v.resize(5);
    }
    for (size_t i = 0; i < v.size(); ++i) cam.distortion[i] = v[i];
  }
  Eigen::Matrix3d r;
  if (const json* rm = Find(c, {"R", "rotation", "rotation_matrix"})) {
    FVV_RETURN_IF_ERROR(Numbers(*rm, where + ": R", &v));
    if (v.size() != 9) return InvalidArgument(where + ": R must have 9 entries");
    for (int i = 0; i < 9; ++i) r(i / 3, i % 3) = v[i];
  } else if (const json* rv = Find(c, {"rvec", "rotation_vector", "rvecs"})) {
    FVV_RETURN_IF_ERROR(Numbers(*rv, where + ": rvec", &v));
    if (v.size() != 3) return InvalidArgument(where + ": rvec must have 3 entries");
    const Eigen::Vector3d w(v[0], v[1], v[2]);
    r = w.norm() < 1e-15 ? Eigen::Matrix3d::Identity()
                         : Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
  } else {
    return InvalidArgument(where + ": no rotation (R or rvec)");
  }
  for (int i = 0; i < 9; ++i) cam.rotation[i] = r(i / 3, i % 3);
  const json* t = Find(c, {"t", "T", "tvec", "translation", "tvecs"});
  if (!t) return InvalidArgument(where + ": no translation (t / tvec)");
  FVV_RETURN_IF_ERROR(Numbers(*t, where + ": t", &v));
  if (v.size() != 3) return InvalidArgument(where + ": t must have 3 entries");
  for (int i = 0; i < 3; ++i) cam.translation[i] = v[i] * unit;
  if (const json* size = Find(c, {"image_size", "imageSize", "size"})) {
    FVV_RETURN_IF_ERROR(Numbers(*size, where + ": image_size", &v));
    if (v.size() != 2) return InvalidArgument(where + ": image_size must be [width, height]");
    cam.width = static_cast<uint32_t>(std::max(0.0, v[0]));
    cam.height = static_cast<uint32_t>(std::max(0.0, v[1]));
  } else {
    const json* w = Find(c, {"width", "image_width", "imageWidth"});
    const json* h = Find(c, {"height", "image_height", "imageHeight"});
    if (!w || !h || !w->is_number() || !h->is_number()) {
      return InvalidArgument(where + ": no image size (width/height or image_size)");
    }
    cam.width = static_cast<uint32_t>(std::max(0.0, w->get<double>()));
    cam.height = static_cast<uint32_t>(std::max(0.0, h->get<double>()));
  }
  FVV_RETURN_IF_ERROR(ValidateCalibration(cam, where));
  return cam;
}

}  // namespace

StatusOr<std::vector<Camera>> ImportCalibrationFile(const std::string& path, double unit) {
  if (!(unit > 0)) return InvalidArgument("translation unit must be positive");
  StatusOr<std::vector<uint8_t>> bytes = ReadFileBytes(path, 16u << 20);
  if (!bytes.ok()) return Status(bytes.status().code(), path + ": " + bytes.status().message());
  std::string text(bytes->begin(), bytes->end());
  json root;
  const bool is_toml = path.size() > 5 && path.compare(path.size() - 5, 5, ".toml") == 0;
  try {
    if (is_toml) {
      root = FromToml(toml::parse(text, path));
    } else {
      // OpenCV writes "%YAML:1.0", which is not a valid YAML directive.
      if (text.rfind("%YAML:", 0) == 0) text.erase(0, text.find('\n'));
      root = FromYaml(YAML::Load(text));
    }
  } catch (const std::exception& e) {
    return InvalidArgument(path + ": cannot parse " + (is_toml ? "TOML" : "YAML") + ": " +
                           e.what());
  }
  if (!root.is_object()) return InvalidArgument(path + ": expected a map of calibration entries");
  std::string stem = path.substr(path.find_last_of('/') + 1);
  stem = stem.substr(0, stem.find('.'));
  std::vector<Camera> out;
  if (Find(root, {"K", "camera_matrix", "cameraMatrix", "intrinsics", "intrinsic"})) {
    StatusOr<Camera> c = CameraFrom(root, stem, unit, path);
    if (!c.ok()) return c.status();
    out.push_back(*c);
    return out;
  }
  for (const auto& [name, value] : root.items()) {
    if (!value.is_object()) continue;
    if (!Find(value, {"K", "camera_matrix", "cameraMatrix", "intrinsics", "intrinsic"})) continue;
    StatusOr<Camera> c = CameraFrom(value, name, unit, path + ": " + name);
    if (!c.ok()) return c.status();
    out.push_back(*c);
  }
  if (out.empty())
    return InvalidArgument(path + ": no camera found (no K / camera_matrix anywhere)");
  return out;
}

}  // namespace fvv
