#include "encoder/capture/calibration_import.h"

#include <tinyxml2.h>
#include <toml++/toml.h>
#include <yaml-cpp/yaml.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>

#include "encoder/capture/calibration.h"
#include "encoder/io/image_io.h"

namespace fvv {
namespace {

using nlohmann::json;

const std::initializer_list<const char*> kMatrixKeys = {
    "K", "camera_matrix", "cameraMatrix", "intrinsics", "intrinsic", "matrix"};
// A per-camera override of the translation unit (formats that fix their own).
constexpr const char* kUnitKey = "fvv_translation_unit";
// Qualisys distortion coefficients as the file gives them (see QualisysEntries).
constexpr double kQualisysDistortionScale = 1.0;

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
      if (n.Tag() == "!") return s;  // quoted: a name such as "01" stays a string
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

// An image width or height as a file writes it: a whole number of pixels in the range
// ValidateCalibration accepts, checked before it becomes an integer.
Status ImageDimension(double v, const std::string& what, uint32_t* out) {
  if (!std::isfinite(v) || v < 1 || v > 16384 || v != std::floor(v)) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", v);
    return InvalidArgument(what + " " + text + " is not a whole number of pixels in 1..16384");
  }
  *out = static_cast<uint32_t>(v);
  return Status::Ok();
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
                            const std::string& where, bool size_optional) {
  Camera cam;
  cam.name = name;
  std::vector<double> v;
  const json* k = Find(c, kMatrixKeys);
  if (!k) return InvalidArgument(where + ": no camera matrix (K / camera_matrix)");
  FVV_RETURN_IF_ERROR(Numbers(*k, where + ": K", &v));
  if (v.size() != 9) return InvalidArgument(where + ": K must have 9 entries");
  cam.fx = v[0], cam.cx = v[2], cam.fy = v[4], cam.cy = v[5];
  if (const json* d = Find(c, {"D", "dist", "distortion", "distortions", "dist_coeffs",
                               "distortion_coefficients", "distCoeffs"})) {
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
  const json* rm = Find(c, {"R", "rotation", "rotation_matrix"});
  const json* rv = Find(c, {"rvec", "rotation_vector", "rvecs"});
  if (rm) FVV_RETURN_IF_ERROR(Numbers(*rm, where + ": R", &v));
  if (rm && v.size() == 9) {
    for (int i = 0; i < 9; ++i) r(i / 3, i % 3) = v[i];
  } else if (rm && v.size() != 3) {
    return InvalidArgument(where + ": R must have 9 entries (a matrix) or 3 (a rotation vector)");
  } else if (rm || rv) {
    // A rotation vector (Rodrigues): anipose, Pose2Sim and FreeMoCap write
    // `rotation` so, EasyMocap `R_<camera>`.
    if (!rm) FVV_RETURN_IF_ERROR(Numbers(*rv, where + ": rvec", &v));
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
  if (const json* own = Find(c, {kUnitKey}); own && own->is_number()) unit = own->get<double>();
  for (int i = 0; i < 3; ++i) cam.translation[i] = v[i] * unit;
  if (const json* size = Find(c, {"image_size", "imageSize", "size"})) {
    FVV_RETURN_IF_ERROR(Numbers(*size, where + ": image_size", &v));
    if (v.size() != 2) return InvalidArgument(where + ": image_size must be [width, height]");
    FVV_RETURN_IF_ERROR(ImageDimension(v[0], where + ": image width", &cam.width));
    FVV_RETURN_IF_ERROR(ImageDimension(v[1], where + ": image height", &cam.height));
  } else {
    const json* w = Find(c, {"width", "image_width", "imageWidth"});
    const json* h = Find(c, {"height", "image_height", "imageHeight"});
    if (w && h && w->is_number() && h->is_number()) {
      FVV_RETURN_IF_ERROR(ImageDimension(w->get<double>(), where + ": image width", &cam.width));
      FVV_RETURN_IF_ERROR(ImageDimension(h->get<double>(), where + ": image height", &cam.height));
    } else if (!size_optional) {
      return InvalidArgument(where + ": no image size (width/height or image_size)");
    }
  }
  // Without a size (EasyMocap keeps none), the frames give it later; validate then.
  if (cam.width > 0 && cam.height > 0) FVV_RETURN_IF_ERROR(ValidateCalibration(cam, where));
  return cam;
}

// One camera's fields as a file gives them, before files are merged.
struct Entry {
  std::string name;
  json fields;
  std::string where;        // file (and section) for messages
  std::string format = "";  // the file's (ParseFile), set as files are merged
};

// EasyMocap: `names` lists the cameras; intri.yml holds K_<name> and
// dist_<name>, extri.yml R_<name> (a rotation vector), Rot_<name> (the matrix)
// and T_<name>; an image size, where given, as H_<name> and W_<name>.
Status EasyMocapEntries(const json& root, const std::string& path, std::vector<Entry>* out) {
  const json& names = root["names"];
  if (!names.is_array()) return InvalidArgument(path + ": \"names\" must be a list of cameras");
  for (const json& n : names) {
    if (!n.is_string() && !n.is_number()) {
      return InvalidArgument(path + ": \"names\" must hold camera names");
    }
    const std::string name = n.is_string() ? n.get<std::string>() : n.dump();
    Entry e{name, json::object(), path + ": camera " + name};
    static const std::pair<const char*, const char*> kMap[] = {
        {"K_", "K"}, {"dist_", "D"},   {"D_", "D"},    {"Rot_", "R"},
        {"T_", "t"}, {"H_", "height"}, {"W_", "width"}};
    for (const auto& [prefix, key] : kMap) {
      auto it = root.find(prefix + name);
      if (it != root.end()) e.fields[key] = *it;
    }
    auto rvec = root.find("R_" + name);
    if (rvec != root.end() && !e.fields.contains("R")) e.fields["rvec"] = *rvec;
    out->push_back(std::move(e));
  }
  return Status::Ok();
}

double Attribute(const tinyxml2::XMLElement* e, const char* name, bool* ok) {
  double v = 0;
  if (!e || e->QueryDoubleAttribute(name, &v) != tinyxml2::XML_SUCCESS || !std::isfinite(v)) {
    *ok = false;
  }
  return v;
}

// Qualisys Track Manager's calibration export (.qca.txt, XML). Per camera:
// `transform` is the camera's pose in the lab (x, y, z in mm; the rotation
// r11..r33 read row by row is M, and world to camera is M then a half turn
// about the camera's x axis, since Qualisys camera axes point otherwise than
// OpenCV's); `intrinsic` focal lengths and principal point in 1/64 pixel on
// the sensor; `fov_video` the image window on the sensor (inclusive pixel
// bounds), whose left/top shift the principal point.
Status QualisysEntries(const std::string& text, const std::string& path, std::vector<Entry>* out) {
  tinyxml2::XMLDocument doc;
  if (doc.Parse(text.data(), text.size()) != tinyxml2::XML_SUCCESS) {
    return InvalidArgument(path + ": cannot parse XML: " + doc.ErrorStr());
  }
  const tinyxml2::XMLElement* root = doc.FirstChildElement("calibration");
  const tinyxml2::XMLElement* cameras = root ? root->FirstChildElement("cameras") : nullptr;
  if (!cameras) return InvalidArgument(path + ": not a Qualisys calibration (no <cameras>)");
  int index = 0;
  for (const tinyxml2::XMLElement* c = cameras->FirstChildElement("camera"); c;
       c = c->NextSiblingElement("camera"), ++index) {
    const char* serial = c->Attribute("serial");
    const std::string name = serial ? serial : "camera" + std::to_string(index);
    const std::string where = path + ": camera " + name;
    const char* active = c->Attribute("active");
    if (active && std::string(active) == "0") continue;
    const tinyxml2::XMLElement* fov = c->FirstChildElement("fov_video");
    const tinyxml2::XMLElement* in = c->FirstChildElement("intrinsic");
    const tinyxml2::XMLElement* tr = c->FirstChildElement("transform");
    if (!fov || !in || !tr) {
      return InvalidArgument(where + ": needs <fov_video>, <intrinsic> and <transform>");
    }
    bool ok = true;
    const double left = Attribute(fov, "left", &ok), top = Attribute(fov, "top", &ok);
    const double right = Attribute(fov, "right", &ok), bottom = Attribute(fov, "bottom", &ok);
    const double fu = Attribute(in, "focalLengthU", &ok), fv = Attribute(in, "focalLengthV", &ok);
    const double cu = Attribute(in, "centerPointU", &ok), cv = Attribute(in, "centerPointV", &ok);
    double d[5];
    const char* dist_names[5] = {"radialDistortion1", "radialDistortion2", "tangentalDistortion1",
                                 "tangentalDistortion2", "radialDistortion3"};
    for (int i = 0; i < 5; ++i) d[i] = Attribute(in, dist_names[i], &ok) * kQualisysDistortionScale;
    Eigen::Matrix3d m;
    const char* r_names[9] = {"r11", "r12", "r13", "r21", "r22", "r23", "r31", "r32", "r33"};
    for (int i = 0; i < 9; ++i) m(i / 3, i % 3) = Attribute(tr, r_names[i], &ok);
    const Eigen::Vector3d centre(Attribute(tr, "x", &ok) / 1000, Attribute(tr, "y", &ok) / 1000,
                                 Attribute(tr, "z", &ok) / 1000);
    if (!ok) return InvalidArgument(where + ": a missing or non-numeric attribute");
    if (right < left || bottom < top) return InvalidArgument(where + ": <fov_video> is empty");
    const Eigen::Matrix3d half_turn_x = Eigen::Vector3d(1, -1, -1).asDiagonal();
    const Eigen::Matrix3d r = half_turn_x * m;
    const Eigen::Vector3d t = -r * centre;
    Entry e{name, json::object(), where};
    e.fields["K"] = {fu / 64, 0, cu / 64 - left, 0, fv / 64, cv / 64 - top, 0, 0, 1};
    e.fields["D"] = {d[0], d[1], d[2], d[3], d[4]};
    e.fields["R"] = json::array();
    for (int i = 0; i < 9; ++i) e.fields["R"].push_back(r(i / 3, i % 3));
    e.fields["t"] = {t.x(), t.y(), t.z()};
    e.fields[kUnitKey] = 1.0;  // the format is in millimetres, converted above
    e.fields["width"] = right - left + 1;
    e.fields["height"] = bottom - top + 1;
    out->push_back(std::move(e));
  }
  if (out->empty()) return InvalidArgument(path + ": no active camera in the calibration");
  return Status::Ok();
}

// OpenCV YAML, plain YAML and TOML: one camera at the top level, or one per
// section (a section's `name` field, where it has one, names the camera).
void SectionEntries(const json& root, const std::string& path, std::vector<Entry>* out) {
  std::string stem = path.substr(path.find_last_of('/') + 1);
  stem = stem.substr(0, stem.find('.'));
  if (Find(root, kMatrixKeys)) {
    out->push_back({stem, root, path});
    return;
  }
  for (const auto& [key, value] : root.items()) {
    if (!value.is_object() || !Find(value, kMatrixKeys)) continue;
    const json* name = Find(value, {"name"});
    const std::string camera = name && name->is_string() ? name->get<std::string>() : key;
    out->push_back({camera, value, path + ": " + key});
  }
}

bool EndsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

StatusOr<std::string> ParseFile(const std::string& path, std::vector<Entry>* out) {
  StatusOr<std::vector<uint8_t>> bytes = ReadFileBytes(path, 16u << 20);
  if (!bytes.ok()) return Status(bytes.status().code(), path + ": " + bytes.status().message());
  std::string text(bytes->begin(), bytes->end());
  const size_t first = text.find_first_not_of(" \t\r\n");
  if (EndsWith(path, ".qca.txt") || EndsWith(path, ".xml") ||
      (first != std::string::npos && text[first] == '<')) {
    FVV_RETURN_IF_ERROR(QualisysEntries(text, path, out));
    return std::string("Qualisys");
  }
  const bool is_toml = EndsWith(path, ".toml");
  json root;
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
  if (root.contains("names") && root["names"].is_array()) {
    FVV_RETURN_IF_ERROR(EasyMocapEntries(root, path, out));
    return std::string("EasyMocap");
  }
  SectionEntries(root, path, out);
  if (out->empty()) {
    return InvalidArgument(path + ": no camera found (no K / camera_matrix / matrix anywhere)");
  }
  return std::string(is_toml ? "TOML" : "YAML");
}

}  // namespace

StatusOr<ImportedCalibration> ImportCalibrationFiles(const std::vector<std::string>& paths,
                                                     double unit) {
  if (!(unit > 0)) return InvalidArgument("translation unit must be positive");
  if (paths.empty()) return InvalidArgument("no calibration file given");
  ImportedCalibration result;
  // Cameras in order of first mention; a later file of the same format adds
  // the fields an earlier one lacks (EasyMocap's extrinsics), never replaces
  // one. Two formats name their fields apart, so a camera both describe would
  // mix two calibrations field by field without a clash: refused.
  std::vector<Entry> merged;
  for (const std::string& path : paths) {
    std::vector<Entry> entries;
    StatusOr<std::string> format = ParseFile(path, &entries);
    if (!format.ok()) return format.status();
    if (result.format.find(*format) == std::string::npos) {
      result.format += (result.format.empty() ? "" : ", ") + *format;
    }
    // Qualisys Track Manager's lab frame is z up (its default, and what its
    // exports give); the other formats leave the world's axes to the rig.
    if (*format == "Qualisys") result.up_axis = 'z';
    for (Entry& e : entries) {
      e.format = *format;
      auto same = std::find_if(merged.begin(), merged.end(),
                               [&](const Entry& m) { return m.name == e.name; });
      if (same == merged.end()) {
        merged.push_back(std::move(e));
        continue;
      }
      if (same->format != e.format) {
        return InvalidArgument("two calibrations describe camera " + e.name + ": " + same->where +
                               " (" + same->format + ") and " + e.where + " (" + e.format +
                               "); give one");
      }
      for (const auto& [key, value] : e.fields.items()) {
        if (same->fields.contains(key)) {
          return InvalidArgument(e.where + ": \"" + key + "\" of camera " + e.name +
                                 " is given again (first in " + same->where + ")");
        }
        same->fields[key] = value;
      }
      same->where += " and " + e.where;
    }
  }
  for (const Entry& e : merged) {
    StatusOr<Camera> c = CameraFrom(e.fields, e.name, unit, e.where, /*size_optional=*/true);
    if (!c.ok()) return c.status();
    result.cameras.push_back(*c);
  }
  return result;
}

StatusOr<std::vector<Camera>> ImportCalibrationFile(const std::string& path, double unit) {
  StatusOr<ImportedCalibration> imported = ImportCalibrationFiles({path}, unit);
  if (!imported.ok()) return imported.status();
  for (const Camera& c : imported->cameras) {
    if (c.width == 0 || c.height == 0) {
      return InvalidArgument(path + ": camera " + c.name +
                             ": no image size (width/height or image_size)");
    }
  }
  return std::move(imported->cameras);
}

Status FitImageSize(uint32_t width, uint32_t height, Camera* camera, std::string* note) {
  note->clear();
  const std::string what = "camera " + camera->name;
  if (camera->width != 0 && (camera->width != width || camera->height != height)) {
    const long dw = static_cast<long>(width) - static_cast<long>(camera->width);
    const long dh = static_cast<long>(height) - static_cast<long>(camera->height);
    char text[256];
    std::snprintf(text, sizeof(text),
                  "%s: the calibration's image is %ux%u, its frames are %ux%u (%+ld x %+ld "
                  "pixels); using the frames' size, principal point unchanged",
                  camera->name.c_str(), camera->width, camera->height, width, height, dw, dh);
    *note = text;
  }
  camera->width = width;
  camera->height = height;
  if (camera->cx < 0 || camera->cx > width || camera->cy < 0 || camera->cy > height) {
    char text[160];
    std::snprintf(text, sizeof(text), ": principal point (%.1f, %.1f) lies outside the %ux%u image",
                  camera->cx, camera->cy, width, height);
    return InvalidArgument(what + text);
  }
  return ValidateCalibration(*camera, what);
}

}  // namespace fvv
