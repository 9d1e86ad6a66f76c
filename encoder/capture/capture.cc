#include "encoder/capture/capture.h"

#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "encoder/capture/calibration.h"
#include "encoder/capture/colour_gain.h"
#include "encoder/capture/video_reader.h"

namespace fvv {
namespace {

using nlohmann::json;

// Errors name the place in capture.json: `cameras[2] ("left"): K: ...`.
class Where {
 public:
  explicit Where(std::string path) : path_(std::move(path)) {}
  Status Bad(const std::string& what) const {
    return InvalidArgument("capture.json: " + path_ + ": " + what);
  }
  Where Child(const std::string& key) const { return Where(path_ + "." + key); }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

Status GetNumber(const json& j, const Where& w, double* out) {
  if (!j.is_number()) return w.Bad("expected a number, got " + std::string(j.type_name()));
  *out = j.get<double>();
  if (!std::isfinite(*out)) return w.Bad("not a finite number");
  return Status::Ok();
}

Status GetMatrix(const json& j, const Where& w, int rows, int cols, double* out) {
  // Either nested rows [[...], ...] or one flat row-major list.
  std::vector<const json*> flat;
  if (j.is_array() && j.size() == size_t(rows) && rows > 1 && j[0].is_array()) {
    for (const json& row : j) {
      if (!row.is_array() || row.size() != size_t(cols)) {
        return w.Bad("expected " + std::to_string(rows) + " rows of " + std::to_string(cols) +
                     " numbers");
      }
      for (const json& v : row) flat.push_back(&v);
    }
  } else if (j.is_array() && j.size() == size_t(rows * cols)) {
    for (const json& v : j) flat.push_back(&v);
  } else {
    return w.Bad("expected a " + std::to_string(rows) + "x" + std::to_string(cols) +
                 " matrix (nested rows or " + std::to_string(rows * cols) + " numbers)");
  }
  for (size_t i = 0; i < flat.size(); ++i) {
    Status s = GetNumber(*flat[i], w, &out[i]);
    if (!s.ok()) return s;
  }
  return Status::Ok();
}

Status CheckPattern(const std::string& pattern, const Where& w) {
  // Exactly one integer conversion %d or %0Nd; other '%' only as "%%".
  int conversions = 0;
  for (size_t i = 0; i < pattern.size(); ++i) {
    if (pattern[i] != '%') continue;
    if (i + 1 < pattern.size() && pattern[i + 1] == '%') {
      ++i;
      continue;
    }
    size_t k = i + 1;
    while (k < pattern.size() && std::isdigit(static_cast<unsigned char>(pattern[k]))) ++k;
    if (k >= pattern.size() || pattern[k] != 'd' || k - i > 3) {
      return w.Bad("pattern \"" + pattern + "\" may only use %d or %0Nd (N < 10)");
    }
    ++conversions;
    i = k;
  }
  if (conversions != 1) {
    return w.Bad("pattern \"" + pattern + "\" needs exactly one frame number (%d or %06d)");
  }
  if (pattern.find("..") != std::string::npos && pattern[0] == '/') {
    return w.Bad("pattern must be a plain path");
  }
  return Status::Ok();
}

Status ParseSource(const json& j, const Where& w, FrameSource* out) {
  if (!j.is_object()) return w.Bad("expected an object with \"images\" or \"video\"");
  const bool images = j.contains("images"), video = j.contains("video");
  if (images == video) return w.Bad("give exactly one of \"images\" (a pattern) or \"video\"");
  const json& path = images ? j["images"] : j["video"];
  if (!path.is_string() || path.get<std::string>().empty()) {
    return w.Child(images ? "images" : "video").Bad("expected a non-empty path string");
  }
  out->kind = images ? FrameSource::Kind::kImages : FrameSource::Kind::kVideo;
  out->path = path.get<std::string>();
  if (images) {
    Status s = CheckPattern(out->path, w.Child("images"));
    if (!s.ok()) return s;
  }
  out->first = 0;
  if (j.contains("first")) {
    if (!j["first"].is_number_integer() || j["first"].get<int64_t>() < 0 ||
        j["first"].get<int64_t>() > 1000000000) {
      return w.Child("first").Bad("expected an integer in 0..1e9");
    }
    out->first = j["first"].get<int64_t>();
  }
  return Status::Ok();
}

json SourceToJson(const FrameSource& s) {
  json j;
  if (s.kind == FrameSource::Kind::kImages) {
    j["images"] = s.path;
    j["first"] = s.first;
  } else {
    j["video"] = s.path;
    if (s.first) j["first"] = s.first;
  }
  return j;
}

Status ParseCamera(const json& j, const Where& w, CaptureCamera* out) {
  if (!j.is_object()) return w.Bad("expected an object");
  for (const char* key : {"name", "width", "height", "K", "R", "t", "frames"}) {
    if (!j.contains(key)) return w.Bad(std::string("missing \"") + key + "\"");
  }
  Camera& c = out->calibration;
  if (!j["name"].is_string() || j["name"].get<std::string>().empty() ||
      j["name"].get<std::string>().size() > 255) {
    return w.Child("name").Bad("expected a name of 1..255 characters");
  }
  c.name = j["name"].get<std::string>();
  for (const char* key : {"width", "height"}) {
    if (!j[key].is_number_integer() || j[key].get<int64_t>() < 1 || j[key].get<int64_t>() > 16384) {
      return w.Child(key).Bad("expected an integer in 1..16384");
    }
  }
  c.width = j["width"].get<uint32_t>();
  c.height = j["height"].get<uint32_t>();
  double k[9];
  Status s = GetMatrix(j["K"], w.Child("K"), 3, 3, k);
  if (!s.ok()) return s;
  if (k[1] != 0 || k[3] != 0 || k[6] != 0 || k[7] != 0 || k[8] != 1) {
    return w.Child("K").Bad("expected [[fx, 0, cx], [0, fy, cy], [0, 0, 1]] (no skew)");
  }
  c.fx = k[0], c.cx = k[2], c.fy = k[4], c.cy = k[5];
  c.distortion = {};
  if (j.contains("distortion")) {
    const json& d = j["distortion"];
    if (!d.is_array() || d.empty() || d.size() > 5) {
      return w.Child("distortion").Bad("expected up to 5 numbers k1 k2 p1 p2 k3");
    }
    for (size_t i = 0; i < d.size(); ++i) {
      s = GetNumber(d[i], w.Child("distortion"), &c.distortion[i]);
      if (!s.ok()) return s;
    }
  }
  s = GetMatrix(j["R"], w.Child("R"), 3, 3, c.rotation.data());
  if (!s.ok()) return s;
  s = GetMatrix(j["t"], w.Child("t"), 3, 1, c.translation.data());
  if (!s.ok()) return s;
  s = ValidateCalibration(c, "capture.json: " + w.path());
  if (!s.ok()) return s;
  s = ParseSource(j["frames"], w.Child("frames"), &out->frames);
  if (!s.ok()) return s;
  if (j.contains("background")) {
    if (!j["background"].is_string() || j["background"].get<std::string>().empty()) {
      return w.Child("background").Bad("expected an image path");
    }
    out->background = j["background"].get<std::string>();
  }
  if (j.contains("silhouettes")) {
    FrameSource sil;
    s = ParseSource(j["silhouettes"], w.Child("silhouettes"), &sil);
    if (!s.ok()) return s;
    out->silhouettes = sil;
  }
  if (j.contains("colour_gain")) {
    const json& g = j["colour_gain"];
    if (!g.is_array() || g.size() != 3) {
      return w.Child("colour_gain").Bad("expected 3 numbers (R, G and B gains)");
    }
    for (size_t ch = 0; ch < 3; ++ch) {
      s = GetNumber(g[ch], w.Child("colour_gain"), &out->colour_gain[ch]);
      if (!s.ok()) return s;
      if (!(out->colour_gain[ch] >= kMinColourGain && out->colour_gain[ch] <= kMaxColourGain)) {
        return w.Child("colour_gain")
            .Bad("gains must lie in [0.25, 4], not " + std::to_string(out->colour_gain[ch]));
      }
    }
  }
  return Status::Ok();
}

std::string Join(const std::string& dir, const std::string& path) {
  if (path.empty() || path[0] == '/' || dir.empty()) return path;
  return dir + "/" + path;
}

bool IsDirectory(const std::string& path) {
  struct stat st;
  return stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

// A z-up world point X_z is the y-up point X_y = M X_z with M = rows (1 0 0),
// (0 0 1), (0 -1 0), a proper rotation. The camera sees R X_z + t = R M^T X_y + t,
// so its rotation becomes R M^T: row i (a, b, c) turns into (a, c, -b).
void TurnZUpToYUp(Camera* k) {
  for (int i = 0; i < 3; ++i) {
    double* row = &k->rotation[3 * i];
    const double b = row[1];
    row[1] = row[2];
    row[2] = -b;
  }
}

}  // namespace

StatusOr<Capture> ParseCapture(const std::string& json_text, const std::string& directory) {
  json j = json::parse(json_text, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) return InvalidArgument("capture.json: not valid JSON");
  if (!j.is_object()) return InvalidArgument("capture.json: the top level must be an object");
  const Where top("top level");
  if (!j.contains("format") || j["format"] != "fvv-capture") {
    return top.Bad("\"format\" must be \"fvv-capture\"");
  }
  if (!j.contains("version") || !j["version"].is_number_integer()) {
    return top.Bad("missing integer \"version\"");
  }
  if (j["version"].get<int64_t>() != kCaptureFormatVersion) {
    return Unsupported("capture.json: version " + std::to_string(j["version"].get<int64_t>()) +
                       " (this fvv reads version " + std::to_string(kCaptureFormatVersion) + ")");
  }
  Capture c;
  c.directory = directory;
  if (!j.contains("frame_rate")) return top.Bad("missing \"frame_rate\"");
  Status s = GetNumber(j["frame_rate"], Where("frame_rate"), &c.frame_rate);
  if (!s.ok()) return s;
  if (c.frame_rate <= 0 || c.frame_rate > 1000)
    return Where("frame_rate").Bad("must lie in (0, 1000]");
  if (!j.contains("frame_count") || !j["frame_count"].is_number_integer() ||
      j["frame_count"].get<int64_t>() < 1 || j["frame_count"].get<int64_t>() > kMaxCaptureFrames) {
    return Where("frame_count")
        .Bad("expected an integer in 1.." + std::to_string(kMaxCaptureFrames));
  }
  c.frame_count = j["frame_count"].get<uint32_t>();
  if (j.contains("up_axis")) {
    const json& up = j["up_axis"];
    if (!up.is_string() || (up != "y" && up != "z")) {
      return Where("up_axis").Bad("expected \"y\" or \"z\"");
    }
    c.up_axis = up.get<std::string>()[0];
  }
  if (!j.contains("cameras") || !j["cameras"].is_array() || j["cameras"].empty()) {
    return Where("cameras").Bad("expected a non-empty array");
  }
  if (j["cameras"].size() > kMaxCaptureCameras) {
    return Where("cameras").Bad("more than " + std::to_string(kMaxCaptureCameras) + " cameras");
  }
  std::set<std::string> names;
  for (size_t i = 0; i < j["cameras"].size(); ++i) {
    const json& cj = j["cameras"][i];
    std::string label = "cameras[" + std::to_string(i) + "]";
    if (cj.is_object() && cj.contains("name") && cj["name"].is_string()) {
      label += " (\"" + cj["name"].get<std::string>() + "\")";
    }
    CaptureCamera cam;
    s = ParseCamera(cj, Where(label), &cam);
    if (!s.ok()) return s;
    if (!names.insert(cam.calibration.name).second) {
      return Where(label).Bad("duplicate camera name \"" + cam.calibration.name + "\"");
    }
    c.cameras.push_back(std::move(cam));
  }
  c.declared_up_axis = c.up_axis;
  if (c.up_axis == 'z') {
    for (CaptureCamera& cam : c.cameras) TurnZUpToYUp(&cam.calibration);
    c.up_axis = 'y';
  }
  return c;
}

StatusOr<Capture> LoadCapture(const std::string& path) {
  std::string file = path, dir = path;
  if (IsDirectory(path)) {
    file = path + "/capture.json";
  } else {
    const size_t slash = path.find_last_of('/');
    dir = slash == std::string::npos ? "." : path.substr(0, slash);
  }
  StatusOr<std::vector<uint8_t>> bytes = ReadFileBytes(file, 64u << 20);
  if (!bytes.ok()) {
    return IoError("capture " + path + ": cannot read " + file + " (" + bytes.status().message() +
                   ")");
  }
  StatusOr<Capture> c = ParseCapture(std::string(bytes->begin(), bytes->end()), dir);
  if (!c.ok()) return Status(c.status().code(), file + ": " + c.status().message());
  return c;
}

std::string CaptureToJson(const Capture& c) {
  json j;
  j["format"] = "fvv-capture";
  j["version"] = kCaptureFormatVersion;
  j["frame_rate"] = c.frame_rate;
  j["frame_count"] = c.frame_count;
  j["up_axis"] = std::string(1, c.up_axis);
  j["cameras"] = json::array();
  for (const CaptureCamera& cam : c.cameras) {
    const Camera& k = cam.calibration;
    json cj;
    cj["name"] = k.name;
    cj["width"] = k.width;
    cj["height"] = k.height;
    cj["K"] = {{k.fx, 0.0, k.cx}, {0.0, k.fy, k.cy}, {0.0, 0.0, 1.0}};
    cj["distortion"] = k.distortion;
    cj["R"] = {{k.rotation[0], k.rotation[1], k.rotation[2]},
               {k.rotation[3], k.rotation[4], k.rotation[5]},
               {k.rotation[6], k.rotation[7], k.rotation[8]}};
    cj["t"] = k.translation;
    cj["frames"] = SourceToJson(cam.frames);
    if (cam.background) cj["background"] = *cam.background;
    if (cam.silhouettes) cj["silhouettes"] = SourceToJson(*cam.silhouettes);
    if (!IsUnitGain(cam.colour_gain)) cj["colour_gain"] = cam.colour_gain;
    j["cameras"].push_back(cj);
  }
  return j.dump(2) + "\n";
}

Status SaveCapture(const Capture& capture) {
  const std::string text = CaptureToJson(capture);
  return WriteFileAtomic(capture.directory + "/capture.json",
                         reinterpret_cast<const uint8_t*>(text.data()), text.size());
}

std::string FramePath(const Capture& capture, const FrameSource& source, uint32_t frame) {
  if (source.kind == FrameSource::Kind::kVideo) return Join(capture.directory, source.path);
  // The pattern was checked to hold one %d / %0Nd; print the number ourselves
  // rather than hand a user string to printf as a format.
  const size_t at = source.path.find('%');
  size_t pos = at;
  while (source.path[pos] == '%' && pos + 1 < source.path.size() && source.path[pos + 1] == '%') {
    pos = source.path.find('%', pos + 2);
  }
  size_t end = pos + 1;
  int width = 0;
  while (std::isdigit(static_cast<unsigned char>(source.path[end]))) {
    width = width * 10 + (source.path[end] - '0');
    ++end;
  }
  std::string number = std::to_string(source.first + frame);
  if (number.size() < size_t(width)) number.insert(0, width - number.size(), '0');
  std::string name = source.path.substr(0, pos) + number + source.path.substr(end + 1);
  // "%%" stands for one '%'.
  for (size_t i = name.find("%%"); i != std::string::npos; i = name.find("%%", i + 1)) {
    name.erase(i, 1);
  }
  return Join(capture.directory, name);
}

namespace {

// Frame `f`'s file of an image-sequence source of camera `cam`.
Status ImageFramePresent(const Capture& capture, const CaptureCamera& cam, const FrameSource& s,
                         uint32_t f) {
  const std::string p = FramePath(capture, s, f);
  struct stat st;
  if (stat(p.c_str(), &st) != 0) {
    return IoError("camera \"" + cam.calibration.name + "\", frame " + std::to_string(f) +
                   ": missing file " + p);
  }
  return Status::Ok();
}

}  // namespace

Status CheckFramesPresent(const Capture& capture, const std::vector<uint32_t>& frames) {
  if (frames.empty()) return Status::Ok();
  const uint32_t last = *std::max_element(frames.begin(), frames.end());
  for (const CaptureCamera& cam : capture.cameras) {
    std::vector<const FrameSource*> sources = {&cam.frames};
    if (cam.silhouettes) sources.push_back(&*cam.silhouettes);
    for (const FrameSource* s : sources) {
      if (s->kind != FrameSource::Kind::kVideo) {
        for (uint32_t f : frames) FVV_RETURN_IF_ERROR(ImageFramePresent(capture, cam, *s, f));
        continue;
      }
      const std::string path = FramePath(capture, *s, 0);
      StatusOr<VideoInfo> info = ProbeVideo(path);
      const std::string label = "camera \"" + cam.calibration.name + "\"";
      if (!info.ok()) return Status(info.status().code(), label + ": " + info.status().message());
      const uint64_t wanted = uint64_t(s->first) + last;
      if (info->frames > 0 && wanted >= info->frames) {
        return IoError(label + ": video " + path + ": no frame " + std::to_string(info->frames) +
                       " (its container says it holds " + std::to_string(info->frames) +
                       " frames; the work asked for reads up to its frame " +
                       std::to_string(wanted) + ")");
      }
    }
  }
  return Status::Ok();
}

struct CaptureReader::Video {
  std::unique_ptr<VideoReader> frames, silhouettes;
};

CaptureReader::CaptureReader(Capture capture) : capture_(std::move(capture)) {
  videos_.resize(capture_.cameras.size());
  for (auto& v : videos_) v = std::make_unique<Video>();
}
CaptureReader::~CaptureReader() = default;

bool CaptureReader::HasSilhouettes() const {
  for (const CaptureCamera& c : capture_.cameras) {
    if (!c.silhouettes) return false;
  }
  return true;
}

bool CaptureReader::HasBackgrounds() const {
  for (const CaptureCamera& c : capture_.cameras) {
    if (!c.background) return false;
  }
  return true;
}

StatusOr<Image> CaptureReader::Read(uint32_t camera, const FrameSource& source, uint32_t frame,
                                    int channels, const char* what) {
  if (camera >= capture_.cameras.size()) {
    return InvalidArgument("camera " + std::to_string(camera) + " does not exist (capture has " +
                           std::to_string(capture_.cameras.size()) + ")");
  }
  const Camera& cal = capture_.cameras[camera].calibration;
  const std::string label =
      std::string(what) + " of camera \"" + cal.name + "\", frame " + std::to_string(frame);
  if (frame >= capture_.frame_count) {
    return InvalidArgument(label + ": beyond frame_count " + std::to_string(capture_.frame_count));
  }
  Image image;
  if (source.kind == FrameSource::Kind::kVideo) {
    std::unique_ptr<VideoReader>& reader =
        channels == 1 ? videos_[camera]->silhouettes : videos_[camera]->frames;
    // The video's own frame: `first` frames are skipped (a camera that
    // started recording early).
    const uint64_t wanted = uint64_t(source.first) + frame;
    if (!reader || reader->next_index() > wanted) {
      reader.reset();
      StatusOr<std::unique_ptr<VideoReader>> opened =
          VideoReader::Open(FramePath(capture_, source, frame), cal.width, cal.height, channels);
      if (!opened.ok())
        return Status(opened.status().code(), label + ": " + opened.status().message());
      reader = std::move(*opened);
    }
    while (true) {
      StatusOr<Image> next = reader->Next();
      if (!next.ok()) {
        reader.reset();
        return Status(next.status().code(), label + ": " + next.status().message());
      }
      if (reader->next_index() == wanted + 1) {
        image = std::move(*next);
        break;
      }
    }
  } else {
    StatusOr<Image> read = ReadImage(FramePath(capture_, source, frame));
    if (!read.ok()) return Status(read.status().code(), label + ": " + read.status().message());
    image = std::move(*read);
  }
  if (image.width != cal.width || image.height != cal.height) {
    return Corrupt(label + ": image is " + std::to_string(image.width) + "x" +
                   std::to_string(image.height) + ", the calibration says " +
                   std::to_string(cal.width) + "x" + std::to_string(cal.height));
  }
  if (image.channels != channels) {
    // Grey frames become RGB; colour silhouettes become grey by their maximum.
    Image converted;
    converted.width = image.width;
    converted.height = image.height;
    converted.channels = channels;
    const size_t n = size_t{image.width} * image.height;
    converted.pixels.resize(n * channels);
    for (size_t i = 0; i < n; ++i) {
      if (channels == 3) {
        for (int k = 0; k < 3; ++k) converted.pixels[3 * i + k] = image.pixels[i];
      } else {
        converted.pixels[i] =
            std::max({image.pixels[3 * i], image.pixels[3 * i + 1], image.pixels[3 * i + 2]});
      }
    }
    image = std::move(converted);
  }
  return image;
}

StatusOr<Image> CaptureReader::ReadFrame(uint32_t camera, uint32_t frame) {
  if (camera >= capture_.cameras.size())
    return InvalidArgument("no camera " + std::to_string(camera));
  return Read(camera, capture_.cameras[camera].frames, frame, 3, "frame");
}

StatusOr<Image> CaptureReader::ReadSilhouette(uint32_t camera, uint32_t frame) {
  if (camera >= capture_.cameras.size())
    return InvalidArgument("no camera " + std::to_string(camera));
  const CaptureCamera& cam = capture_.cameras[camera];
  if (!cam.silhouettes) {
    return InvalidArgument("camera \"" + cam.calibration.name + "\" has no silhouettes");
  }
  StatusOr<Image> s = Read(camera, *cam.silhouettes, frame, 1, "silhouette");
  if (!s.ok()) return s;
  for (uint8_t& p : s->pixels) p = p ? 255 : 0;
  return s;
}

StatusOr<Image> CaptureReader::ReadBackground(uint32_t camera) {
  if (camera >= capture_.cameras.size())
    return InvalidArgument("no camera " + std::to_string(camera));
  const CaptureCamera& cam = capture_.cameras[camera];
  const std::string label = "background of camera \"" + cam.calibration.name + "\"";
  if (!cam.background) return InvalidArgument(label + ": none given");
  StatusOr<Image> image = ReadImage(Join(capture_.directory, *cam.background));
  if (!image.ok()) return Status(image.status().code(), label + ": " + image.status().message());
  if (image->width != cam.calibration.width || image->height != cam.calibration.height) {
    return Corrupt(label + ": image size differs from the calibration's");
  }
  if (image->channels != 3) return Corrupt(label + ": expected an RGB image");
  return image;
}

Status CaptureReader::CheckFiles() {
  for (uint32_t c = 0; c < capture_.cameras.size(); ++c) {
    const CaptureCamera& cam = capture_.cameras[c];
    std::vector<const FrameSource*> sources = {&cam.frames};
    if (cam.silhouettes) sources.push_back(&*cam.silhouettes);
    for (const FrameSource* s : sources) {
      if (s->kind == FrameSource::Kind::kVideo) {
        StatusOr<std::unique_ptr<VideoReader>> v = VideoReader::Open(
            FramePath(capture_, *s, 0), cam.calibration.width, cam.calibration.height);
        if (!v.ok())
          return Status(v.status().code(),
                        "camera \"" + cam.calibration.name + "\": " + v.status().message());
        continue;
      }
      for (uint32_t f = 0; f < capture_.frame_count; ++f)
        FVV_RETURN_IF_ERROR(ImageFramePresent(capture_, cam, *s, f));
    }
    if (cam.background) {
      const std::string p = Join(capture_.directory, *cam.background);
      struct stat st;
      if (stat(p.c_str(), &st) != 0) {
        return IoError("camera \"" + cam.calibration.name + "\": missing background " + p);
      }
    }
  }
  return Status::Ok();
}

}  // namespace fvv
