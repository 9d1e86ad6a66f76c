#include "encoder/cli/render_command.h"

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <glm/gtc/matrix_transform.hpp>
#include <memory>
#include <string>

#include "fvv/fvv_decoder.hpp"
#include "player/render/headless.h"
#include "player/render/renderer.h"
#include "tools/imageio/image_io.h"

namespace fvv {
namespace {

struct RenderArgs {
  std::string input, output_dir, size = "640x480", format = "png";
  uint32_t first = 0, last = UINT32_MAX;
  int camera = -1;     // -1: orbit
  uint32_t sheet = 0;  // > 0: a contact sheet of this many novel views of --first
  float exponent = 4.0f;
  uint64_t bytes = 0;
  double max_ms = 0;
};

int Fail(const std::string& m) {
  std::fprintf(stderr, "fvv: %s\n", m.c_str());
  return 1;
}

int RunRender(const RenderArgs& a) {
  int width = 0, height = 0;
  if (std::sscanf(a.size.c_str(), "%dx%d", &width, &height) != 2) {
    return Fail("--size " + a.size + ": expected WxH, e.g. 1280x720");
  }
  DecoderPtr dec = MakeDecoder();
  if (!dec || fvv_decoder_open_file(dec.get(), a.input.c_str()) != FVV_OK) {
    return Fail(dec ? fvv_decoder_error(dec.get()) : "cannot create a decoder");
  }
  fvv_stream_info info;
  fvv_decoder_get_info(dec.get(), &info);
  const uint32_t last = std::min(a.last, info.frame_count - 1);
  if (a.first > last)
    return Fail("--first beyond the stream's " + std::to_string(info.frame_count) + " frames");
  if (a.camera >= static_cast<int>(info.camera_count)) {
    return Fail("--camera " + std::to_string(a.camera) + ": the stream has " +
                std::to_string(info.camera_count) + " cameras");
  }
  if (Status s = MakeDirectories(a.output_dir); !s.ok()) return Fail(s.ToString());
  auto ctx = HeadlessContext::Create(width, height);
  if (!ctx.ok()) return Fail(ctx.status().ToString());
  fvv_model model;
  fvv_decoder_get_model(dec.get(), &model);
  std::vector<glm::vec3> centres;
  std::vector<fvv_camera> cameras(info.camera_count);
  for (uint32_t c = 0; c < info.camera_count; ++c) {
    fvv_decoder_get_camera(dec.get(), c, &cameras[c]);
    centres.emplace_back(cameras[c].centre[0], cameras[c].centre[1], cameras[c].centre[2]);
  }
  auto renderer =
      Renderer::Create((*ctx)->gl(), model, centres, info.atlas_width, info.atlas_height);
  if (!renderer.ok()) return Fail(renderer.status().ToString());
  fvv_decode_budget budget{};
  budget.max_bytes_per_gop = a.bytes;
  budget.max_ms_per_gop = a.max_ms;
  using Clock = std::chrono::steady_clock;
  double decode_s = 0, render_s = 0;
  std::vector<uint8_t> rgb;
  if (a.sheet > 0) {
    // Novel views of one frame from evenly spaced directions around the actor,
    // tiled into one image.
    FramePtr frame = DecodeFrame(dec.get(), a.first, &budget);
    if (!frame) return Fail(fvv_decoder_error(dec.get()));
    Status s = (*renderer)->SetFrame(*frame);
    if (!s.ok()) return Fail(s.ToString());
    std::vector<Image> views;
    const glm::vec3 target(frame->bone_world[12], frame->bone_world[13], frame->bone_world[14]);
    for (uint32_t i = 0; i < a.sheet; ++i) {
      RenderView view;
      view.exponent = a.exponent;
      const float angle = 6.2831853f * static_cast<float>(i) / static_cast<float>(a.sheet);
      const float lift = 0.2f + 0.6f * static_cast<float>(i % 2);
      view.eye = target + glm::vec3(3.5f * std::sin(angle), lift, 3.5f * std::cos(angle));
      view.view = glm::lookAt(view.eye, target, glm::vec3(0, 1, 0));
      view.projection =
          glm::perspective(glm::radians(40.0f), float(width) / float(height), 0.05f, 50.0f);
      s = (*renderer)->Draw(view, width, height);
      if (s.ok()) s = (*renderer)->ReadRgb(width, height, &rgb);
      if (!s.ok()) return Fail(s.ToString());
      Image view_image;
      view_image.width = static_cast<uint32_t>(width);
      view_image.height = static_cast<uint32_t>(height);
      view_image.pixels = rgb;
      views.push_back(std::move(view_image));
    }
    const std::string path = a.output_dir + "/contact_sheet." + a.format;
    s = WriteImage(path, MakeContactSheet(views));
    if (!s.ok()) return Fail(s.ToString());
    std::printf("contact sheet of frame %u: %u views of %dx%d -> %s\n", a.first, a.sheet, width,
                height, path.c_str());
    return 0;
  }
  const uint32_t count = last - a.first + 1;
  for (uint32_t f = a.first; f <= last; ++f) {
    auto t0 = Clock::now();
    FramePtr frame = DecodeFrame(dec.get(), f, &budget);
    if (!frame) return Fail("frame " + std::to_string(f) + ": " + fvv_decoder_error(dec.get()));
    decode_s += std::chrono::duration<double>(Clock::now() - t0).count();
    RenderView view;
    view.exponent = a.exponent;
    if (a.camera >= 0) {
      CameraViewProjection(cameras[a.camera], 0.05f, 50.0f, &view.view, &view.projection);
      view.eye = centres[a.camera];
    } else {
      // One orbit over the rendered frames, around the root joint.
      const glm::vec3 target(frame->bone_world[12], frame->bone_world[13], frame->bone_world[14]);
      const float angle = 6.2831853f * static_cast<float>(f - a.first) / static_cast<float>(count);
      view.eye = target + glm::vec3(3.5f * std::sin(angle), 0.4f, 3.5f * std::cos(angle));
      view.view = glm::lookAt(view.eye, target, glm::vec3(0, 1, 0));
      view.projection =
          glm::perspective(glm::radians(40.0f), float(width) / float(height), 0.05f, 50.0f);
    }
    t0 = Clock::now();
    Status s = (*renderer)->SetFrame(*frame);
    if (s.ok()) s = (*renderer)->Draw(view, width, height);
    if (s.ok()) s = (*renderer)->ReadRgb(width, height, &rgb);
    render_s += std::chrono::duration<double>(Clock::now() - t0).count();
    if (!s.ok()) return Fail(s.ToString());
    Image img;
    img.width = static_cast<uint32_t>(width);
    img.height = static_cast<uint32_t>(height);
    img.channels = 3;
    img.pixels = rgb;
    char name[64];
    std::snprintf(name, sizeof(name), "/render_f%05u.%s", f, a.format.c_str());
    s = WriteImage(a.output_dir + name, img);
    if (!s.ok()) return Fail(s.ToString());
  }
  const double play_s = count * double(info.frame_rate_den) / info.frame_rate_num;
  std::printf(
      "rendered frames %u..%u at %dx%d (%s): %.1f fps rendering, decode %.0f ms "
      "(real-time factor %.2f) -> %s\n",
      a.first, last, width, height,
      a.camera >= 0 ? ("camera " + std::to_string(a.camera)).c_str() : "orbit",
      count / std::max(render_s, 1e-9), decode_s * 1e3, decode_s / play_s, a.output_dir.c_str());
  return 0;
}

}  // namespace

void AddRenderCommand(CLI::App* app, int* exit_code) {
  auto args = std::make_shared<RenderArgs>();
  CLI::App* r = app->add_subcommand(
      "render",
      "Render a .fvv stream headless (OSMesa) with Renderer II: the decoded model, textured by "
      "blending the camera textures by viewing angle; writes render_fFFFFF.png per frame");
  r->add_option("file", args->input, ".fvv stream")->required()->check(CLI::ExistingFile);
  r->add_option("-o,--output", args->output_dir, "Output directory")->required();
  r->add_option("--size", args->size, "Image size WxH")->capture_default_str();
  r->add_option("--first", args->first, "First frame")->capture_default_str();
  r->add_option("--last", args->last, "Last frame (default: the stream's last)");
  r->add_option("--camera", args->camera, "Render from capture camera K (default: an orbit)");
  r->add_option("--contact-sheet", args->sheet,
                "Instead: one image of N novel views of frame --first around the actor")
      ->check(CLI::Range(1, 64));
  r->add_option("--exponent", args->exponent,
                "Blend exponent: higher lets the best-aligned camera dominate")
      ->capture_default_str()
      ->check(CLI::Range(0.0f, 64.0f));
  auto* bytes = r->add_option("--bytes", args->bytes, "Texture bytes per GOP fragment to decode");
  r->add_option("--max-ms", args->max_ms, "Texture decoding time per GOP")->excludes(bytes);
  r->add_option("--format", args->format, "Image format")
      ->check(CLI::IsMember({"png", "exr"}))
      ->capture_default_str();
  r->callback([args, exit_code] { *exit_code = RunRender(*args); });
}

}  // namespace fvv
