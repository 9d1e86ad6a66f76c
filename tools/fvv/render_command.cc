#include "tools/fvv/render_command.h"

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <glm/gtc/matrix_transform.hpp>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "encoder/capture/capture.h"
#include "encoder/io/child_process.h"
#include "encoder/io/image_io.h"
#include "fvv/fvv_decoder.hpp"
#include "player/decoder/public_camera.h"
#include "player/render/headless.h"
#include "player/render/renderer.h"
#include "tools/fvv/render_frames.h"

namespace fvv {
namespace {

struct RenderArgs {
  std::string input, output_dir, size = "640x480", format = "png";
  bool size_given = false, coverage = false, surface = false;
  std::string cameras_from, path, video;
  uint32_t first = 0, last = UINT32_MAX;
  int camera = -1;     // -1: orbit
  uint32_t sheet = 0;  // > 0: a contact sheet of this many novel views of --first
  float exponent = RenderView().exponent;
  float facing_exponent = RenderView().facing_exponent;
  std::string renderer = "blend", poses;
  float dominance = 2.0f;
  int expand_px = 3;
  uint64_t bytes = 0;
  double max_ms = 0;
  std::string texture;
};

int Fail(const std::string& m) {
  std::fprintf(stderr, "fvv: %s\n", m.c_str());
  return 1;
}

// A camera path (--path): keyframes of eye, target and field of view, linear
// in between, held before the first and after the last.
struct PathKey {
  double frame = 0;
  glm::vec3 eye{0.0f}, target{0.0f};
  bool target_actor = false;  // "target": "actor" follows the root joint
  float fov_deg = 40.0f;
};

StatusOr<std::vector<PathKey>> LoadPath(const std::string& path) {
  std::ifstream in(path);
  if (!in) return IoError("cannot read " + path);
  nlohmann::json j;
  try {
    in >> j;
  } catch (const nlohmann::json::exception& e) {
    return Corrupt(path + ": not JSON (" + e.what() + ")");
  }
  const auto vec3 = [&](const nlohmann::json& v, const std::string& where) -> StatusOr<glm::vec3> {
    if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() ||
        !v[2].is_number()) {
      return Corrupt(path + ": " + where + ": expected [x, y, z] in metres");
    }
    return glm::vec3(v[0].get<float>(), v[1].get<float>(), v[2].get<float>());
  };
  if (!j.is_object() || !j.contains("keyframes") || !j["keyframes"].is_array() ||
      j["keyframes"].empty()) {
    return Corrupt(path +
                   ": expected {\"keyframes\": [{\"frame\", \"eye\", \"target\", \"fov\"}, ...]}");
  }
  std::vector<PathKey> keys;
  for (size_t i = 0; i < j["keyframes"].size(); ++i) {
    const nlohmann::json& k = j["keyframes"][i];
    const std::string where = "keyframes[" + std::to_string(i) + "]";
    if (!k.is_object() || !k.contains("frame") || !k["frame"].is_number() || !k.contains("eye")) {
      return Corrupt(path + ": " + where + ": needs \"frame\" and \"eye\"");
    }
    PathKey key;
    key.frame = k["frame"].get<double>();
    FVV_ASSIGN_OR_RETURN(key.eye, vec3(k["eye"], where + ".eye"));
    const nlohmann::json target = k.value("target", nlohmann::json("actor"));
    if (target == "actor") {
      key.target_actor = true;
    } else {
      FVV_ASSIGN_OR_RETURN(key.target, vec3(target, where + ".target"));
    }
    key.fov_deg = k.value("fov", 40.0f);
    if (!(key.fov_deg > 1.0f && key.fov_deg < 170.0f)) {
      return Corrupt(path + ": " + where + ".fov: degrees in (1, 170)");
    }
    if (!keys.empty() && key.frame <= keys.back().frame) {
      return Corrupt(path + ": " + where + ".frame: keyframes must be in increasing frame order");
    }
    keys.push_back(key);
  }
  return keys;
}

// The view at `frame` along the path; `actor` is the root joint's position.
void PathView(const std::vector<PathKey>& keys, double frame, const glm::vec3& actor, float aspect,
              RenderView* view) {
  size_t i = 0;
  while (i + 1 < keys.size() && keys[i + 1].frame <= frame) ++i;
  const PathKey& a = keys[i];
  const PathKey& b = keys[std::min(i + 1, keys.size() - 1)];
  const float t =
      b.frame > a.frame
          ? static_cast<float>(std::clamp((frame - a.frame) / (b.frame - a.frame), 0.0, 1.0))
          : 0.0f;
  const glm::vec3 ta = a.target_actor ? actor : a.target, tb = b.target_actor ? actor : b.target;
  view->eye = glm::mix(a.eye, b.eye, t);
  view->view = glm::lookAt(view->eye, glm::mix(ta, tb, t), glm::vec3(0, 1, 0));
  view->projection =
      glm::perspective(glm::radians(a.fov_deg + (b.fov_deg - a.fov_deg) * t), aspect, 0.05f, 50.0f);
}

// Frames piped to ffmpeg (H.264 in MP4), written to a temporary file that
// becomes the output only when ffmpeg succeeds.
class VideoWriter {
 public:
  static StatusOr<std::unique_ptr<VideoWriter>> Open(const std::string& path, int width, int height,
                                                     double fps) {
    if (width % 2 || height % 2) {
      return InvalidArgument("--video needs an even width and height (yuv420p), not " +
                             std::to_string(width) + "x" + std::to_string(height));
    }
    if (!HaveProgram("ffmpeg")) {
      return IoError("--video needs ffmpeg on the PATH (Debian: apt-get install ffmpeg)");
    }
    auto w = std::unique_ptr<VideoWriter>(new VideoWriter);
    w->path_ = path;
    w->temp_ = path + ".part.mp4";
    char rate[32];
    std::snprintf(rate, sizeof(rate), "%.6f", fps);
    StatusOr<std::unique_ptr<ChildProcess>> encoder =
        ChildProcess::Start({"ffmpeg",
                             "-v",
                             "error",
                             "-nostdin",
                             "-y",
                             "-f",
                             "rawvideo",
                             "-pix_fmt",
                             "rgb24",
                             "-s",
                             std::to_string(width) + "x" + std::to_string(height),
                             "-r",
                             rate,
                             "-i",
                             "pipe:0",
                             "-c:v",
                             "libx264",
                             "-preset",
                             "medium",
                             "-crf",
                             "18",
                             "-pix_fmt",
                             "yuv420p",
                             "-f",
                             "mp4",
                             w->temp_},
                            ChildProcess::Pipe::kWriteStdin);
    if (!encoder.ok()) return encoder.status();
    w->encoder_ = std::move(encoder).value();
    return w;
  }
  ~VideoWriter() {
    encoder_.reset();  // killed if still running: the output was not finished
    std::remove(temp_.c_str());
  }
  Status Add(const std::vector<uint8_t>& rgb) {
    if (!encoder_->Write(rgb.data(), rgb.size())) {
      return IoError("ffmpeg stopped taking frames for " + path_);
    }
    return Status::Ok();
  }
  Status Close() {
    const int rc = encoder_->Finish();
    if (rc != 0) return IoError("ffmpeg failed to write " + path_);
    if (std::rename(temp_.c_str(), path_.c_str()) != 0) return IoError("cannot write " + path_);
    return Status::Ok();
  }

 private:
  VideoWriter() = default;
  std::string path_, temp_;
  std::unique_ptr<ChildProcess> encoder_;
};

int RunRender(const RenderArgs& a) {
  if (a.output_dir.empty() && a.video.empty())
    return Fail("give -o DIR, --video FILE.mp4, or both");
  const bool projective = a.renderer == "projective";
  if (!projective && !a.poses.empty()) return Fail("--poses is for --renderer projective");
  if (!projective && a.surface) {
    return Fail("--surface is for --renderer projective (a stream carries its own surface)");
  }
  // Views from another capture's calibrated cameras, e.g. fvv synth's held-out ones.
  std::optional<Camera> from_camera;
  if (!a.cameras_from.empty()) {
    if (a.camera < 0) return Fail("--cameras-from needs --camera K (a camera of that capture)");
    StatusOr<Capture> other = LoadCapture(a.cameras_from);
    if (!other.ok()) return Fail(other.status().ToString());
    if (a.camera >= static_cast<int>(other->cameras.size())) {
      return Fail("--camera " + std::to_string(a.camera) + ": " + a.cameras_from + " has " +
                  std::to_string(other->cameras.size()) + " cameras");
    }
    from_camera = other->cameras[a.camera].calibration;
  }
  std::vector<PathKey> path;
  if (!a.path.empty()) {
    auto keys = LoadPath(a.path);
    if (!keys.ok()) return Fail(keys.status().ToString());
    path = std::move(keys).value();
  }
  int width = 0, height = 0;
  if (from_camera && !a.size_given) {
    width = static_cast<int>(from_camera->width);
    height = static_cast<int>(from_camera->height);
  } else if (std::sscanf(a.size.c_str(), "%dx%d", &width, &height) != 2 || width < 1 ||
             height < 1 || width > 16384 || height > 16384) {
    return Fail("--size " + a.size + ": expected WxH, e.g. 1280x720");
  }
  if (a.sheet > 0 && a.output_dir.empty()) return Fail("--contact-sheet writes into -o DIR");
  StatusOr<std::unique_ptr<RenderFrames>> opened = Internal("no frames");
  if (projective) {
    CaptureRenderOptions o;
    o.poses = a.poses;
    o.first = a.first;
    o.last = a.sheet > 0 ? a.first : a.last;
    o.projective.dominance = a.dominance;
    o.projective.expand_px = a.expand_px;
    o.surface = a.surface;
    if (!a.poses.empty()) {
      std::printf("Renderer I: poses from %s\n", a.poses.c_str());
    } else {
      std::printf("Renderer I: no --poses given, tracking the capture first\n");
      o.progress = [](const std::string& line) { std::printf("  %s\n", line.c_str()); };
    }
    opened = OpenCaptureFrames(a.input, o);
  } else {
    StreamRenderOptions o;
    o.bytes = a.bytes;
    o.max_ms = a.max_ms;
    o.texture = a.texture;
    opened = OpenStreamFrames(a.input, o);
  }
  if (!opened.ok()) return Fail(opened.status().ToString());
  RenderFrames& frames = **opened;
  const uint32_t first = std::max(a.first, frames.first_frame());
  const uint32_t last = std::min(a.last, frames.last_frame());
  if (first > last) {
    return Fail("--first/--last select none of the frames " + std::to_string(frames.first_frame()) +
                ".." + std::to_string(frames.last_frame()) + " of " + a.input);
  }
  const std::vector<fvv_camera>& cameras = frames.cameras();
  if (!from_camera && a.camera >= static_cast<int>(cameras.size())) {
    return Fail("--camera " + std::to_string(a.camera) + ": the " +
                (projective ? "capture" : "stream") + " has " + std::to_string(cameras.size()) +
                " cameras");
  }
  if (!a.output_dir.empty()) {
    if (Status s = MakeDirectories(a.output_dir); !s.ok()) return Fail(s.ToString());
  }
  auto ctx = HeadlessContext::Create(width, height);
  if (!ctx.ok()) return Fail(ctx.status().ToString());
  if (Status s = frames.CreateRenderer((*ctx)->gl()); !s.ok()) return Fail(s.ToString());
  const float aspect = float(width) / float(height);
  const auto orbit_view = [&](const glm::vec3& target, float angle, float lift, RenderView* view) {
    view->eye = target + glm::vec3(3.5f * std::sin(angle), lift, 3.5f * std::cos(angle));
    view->view = glm::lookAt(view->eye, target, glm::vec3(0, 1, 0));
    view->projection = glm::perspective(glm::radians(40.0f), aspect, 0.05f, 50.0f);
  };
  std::vector<uint8_t> rgb;
  if (a.sheet > 0) {
    // Novel views of one frame from evenly spaced directions around the actor,
    // tiled into one image.
    glm::vec3 target;
    Status s = frames.Load(first, &target);
    if (!s.ok()) return Fail(s.ToString());
    std::vector<Image> views;
    for (uint32_t i = 0; i < a.sheet; ++i) {
      RenderView view;
      view.exponent = a.exponent;
      view.facing_exponent = a.facing_exponent;
      const float angle = 6.2831853f * static_cast<float>(i) / static_cast<float>(a.sheet);
      orbit_view(target, angle, 0.2f + 0.6f * static_cast<float>(i % 2), &view);
      s = frames.Draw(view, width, height);
      if (s.ok()) s = frames.ReadRgb(width, height, &rgb);
      if (!s.ok()) return Fail(s.ToString());
      Image view_image;
      view_image.width = static_cast<uint32_t>(width);
      view_image.height = static_cast<uint32_t>(height);
      view_image.pixels = rgb;
      views.push_back(std::move(view_image));
    }
    const std::string sheet_path = a.output_dir + "/contact_sheet." + a.format;
    s = WriteImage(sheet_path, MakeContactSheet(views));
    if (!s.ok()) return Fail(s.ToString());
    std::printf("contact sheet of frame %u: %u views of %dx%d -> %s\n", first, a.sheet, width,
                height, sheet_path.c_str());
    return 0;
  }
  const uint32_t count = last - first + 1;
  std::unique_ptr<VideoWriter> video;
  if (!a.video.empty()) {
    auto v = VideoWriter::Open(a.video, width, height, frames.frame_rate());
    if (!v.ok()) return Fail(v.status().ToString());
    video = std::move(v).value();
  }
  using Clock = std::chrono::steady_clock;
  double render_s = 0;
  for (uint32_t f = first; f <= last; ++f) {
    glm::vec3 root;
    Status s = frames.Load(f, &root);
    if (!s.ok()) return Fail(s.ToString());
    RenderView view;
    view.exponent = a.exponent;
    view.facing_exponent = a.facing_exponent;
    if (!path.empty()) {
      PathView(path, f, root, aspect, &view);
    } else if (from_camera) {
      CameraViewProjection(PublicCamera(*from_camera), 0.05f, 50.0f, &view.view, &view.projection);
      const auto c = from_camera->Centre();
      view.eye = glm::vec3(c[0], c[1], c[2]);
    } else if (a.camera >= 0) {
      const fvv_camera& c = cameras[a.camera];
      CameraViewProjection(c, 0.05f, 50.0f, &view.view, &view.projection);
      view.eye = glm::vec3(c.centre[0], c.centre[1], c.centre[2]);
    } else {
      // One orbit over the rendered frames, around the root joint.
      orbit_view(root, 6.2831853f * static_cast<float>(f - first) / static_cast<float>(count), 0.4f,
                 &view);
    }
    const auto t0 = Clock::now();
    s = frames.Draw(view, width, height);
    if (s.ok()) s = frames.ReadRgb(width, height, &rgb);
    render_s += std::chrono::duration<double>(Clock::now() - t0).count();
    if (!s.ok()) return Fail(s.ToString());
    if (video) {
      s = video->Add(rgb);
      if (!s.ok()) return Fail(s.ToString());
    }
    if (!a.output_dir.empty()) {
      Image img;
      img.width = static_cast<uint32_t>(width);
      img.height = static_cast<uint32_t>(height);
      img.channels = 3;
      img.pixels = rgb;
      char name[64];
      std::snprintf(name, sizeof(name), "/render_f%05u.%s", f, a.format.c_str());
      s = WriteImage(a.output_dir + name, img);
      if (s.ok() && a.coverage) {
        img.channels = 1;
        s = frames.ReadCoverage(width, height, &img.pixels);
        std::snprintf(name, sizeof(name), "/coverage_f%05u.png", f);
        if (s.ok()) s = WriteImage(a.output_dir + name, img);
      }
      if (!s.ok()) return Fail(s.ToString());
    }
  }
  if (video) {
    if (Status s = video->Close(); !s.ok()) return Fail(s.ToString());
  }
  const std::string what = !path.empty() ? "path " + a.path
                           : from_camera
                               ? "camera \"" + from_camera->name + "\" of " + a.cameras_from
                           : a.camera >= 0 ? "camera " + std::to_string(a.camera)
                                           : std::string("orbit");
  std::string where = a.output_dir;
  if (!a.video.empty()) where += (where.empty() ? "" : " and ") + a.video;
  std::printf(
      "rendered frames %u..%u at %dx%d (%s): %.1f fps rendering (draw and read-back); %s -> %s\n",
      first, last, width, height, what.c_str(), count / std::max(render_s, 1e-9),
      frames.LoadTimes(count).c_str(), where.c_str());
  return 0;
}

}  // namespace

void AddRenderCommand(CLI::App* app, int* exit_code) {
  auto args = std::make_shared<RenderArgs>();
  CLI::App* r = app->add_subcommand(
      "render",
      "Render headless (OSMesa): a .fvv stream with Renderer II (the decoded model, textured by "
      "blending the camera textures by viewing angle), or with --renderer projective a capture "
      "with Renderer I (the posed model textured directly from the camera images: a preview "
      "before encoding); writes render_fFFFFF.png per frame");
  r->add_option("file", args->input,
                ".fvv stream (Renderer II), or with --renderer projective a capture directory or "
                "capture.json")
      ->required()
      ->check(CLI::ExistingPath);
  r->add_option("--renderer", args->renderer,
                "blend: Renderer II on a stream; projective: Renderer I on a capture")
      ->check(CLI::IsMember({"blend", "projective"}))
      ->capture_default_str();
  r->add_option("--poses", args->poses,
                "Renderer I: poses.json (fvv track) or a synthetic capture's truth (its "
                "directory); default: track the capture first")
      ->check(CLI::ExistingPath);
  r->add_option("--dominance", args->dominance,
                "Renderer I: how much the camera facing a vertex best dominates the blend")
      ->capture_default_str()
      ->check(CLI::Range(0.0f, 32.0f));
  r->add_option("--expand", args->expand_px,
                "Renderer I: pixels the silhouettes grow by (their ring takes the actor's colour)")
      ->capture_default_str()
      ->check(CLI::Range(0, 32));
  r->add_flag("--surface", args->surface,
              "Renderer I: draw the surface of every frame, tracked from the capture's "
              "silhouettes as fvv encode --surface does, instead of the fitted body (a stream "
              "carries its own: Renderer II draws it)");
  r->add_option("-o,--output", args->output_dir, "Output directory (render_fFFFFF.png per frame)");
  r->add_option("--video", args->video,
                "Also (or instead) write an H.264 MP4 through ffmpeg at the stream's frame rate");
  r->add_option("--size", args->size,
                "Image size WxH (default 640x480, or the --cameras-from camera's image size)")
      ->each([args](const std::string&) { args->size_given = true; });
  r->add_option("--first", args->first, "First frame")->capture_default_str();
  r->add_option("--last", args->last, "Last frame (default: the stream's last)");
  auto* camera =
      r->add_option("--camera", args->camera, "Render from capture camera K (default: an orbit)");
  r->add_option("--cameras-from", args->cameras_from,
                "With --camera K: camera K of this capture (directory or capture.json) instead of "
                "the stream's, e.g. the held-out cameras of fvv synth (CAPTURE/truth/heldout)")
      ->needs(camera);
  r->add_option("--path", args->path,
                "A camera path: JSON {\"keyframes\": [{\"frame\": 0, \"eye\": [x, y, z], "
                "\"target\": [x, y, z] or \"actor\", \"fov\": 40}, ...]}, linear between "
                "keyframes")
      ->excludes(camera)
      ->check(CLI::ExistingFile);
  r->add_option("--contact-sheet", args->sheet,
                "Instead: one image of N novel views of frame --first around the actor")
      ->check(CLI::Range(1, 64));
  r->add_option("--exponent", args->exponent,
                "Renderer II blend exponent: higher lets the best-aligned camera dominate")
      ->capture_default_str()
      ->check(CLI::Range(0.0f, 64.0f));
  r->add_option("--facing-exponent", args->facing_exponent,
                "Renderer II: higher lets the cameras facing the surface squarely dominate")
      ->check(CLI::Range(0.0f, 64.0f))
      ->capture_default_str();
  auto* bytes = r->add_option("--bytes", args->bytes,
                              "Renderer II: texture bytes per GOP fragment to decode");
  auto* max_ms =
      r->add_option("--max-ms", args->max_ms, "Renderer II: texture decoding time per GOP")
          ->excludes(bytes);
  r->add_option("--texture", args->texture,
                "Renderer II with one texture (a PNG of the atlas's size, e.g. what fvv export "
                "wrote) for every camera: the decoded poses without view-dependent blending, as "
                "other tools draw an exported glTF")
      ->check(CLI::ExistingFile)
      ->excludes(bytes)
      ->excludes(max_ms);
  r->add_flag("--coverage", args->coverage,
              "Renderer II: also write coverage_fFFFFF.png per frame, 255 where the actor is "
              "drawn and 0 elsewhere (what a held-out view's scores compare with the person's "
              "mask)");
  r->add_option("--format", args->format, "Image format")
      ->check(CLI::IsMember({"png", "exr"}))
      ->capture_default_str();
  r->callback([args, exit_code] { *exit_code = RunRender(*args); });
}

}  // namespace fvv
