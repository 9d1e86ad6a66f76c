// Renderer II throughput, headless (OSMesa): one decoded frame of a stream is
// drawn from an orbit of viewpoints at a screen size, with nothing else running
// (no decoding alongside), to time the renderer itself: draw only (to glFinish),
// draw + read-back, the per-frame texture upload of every camera, and for a
// stream without masks the cameras' depth maps, which are drawn once per frame
// for the cameras the view blends (the draw figures leave them out).
//
//   build/bench/render_bench STREAM.fvv [--size WxH] [--views N]
// e.g. with the demo's stream (the 23,040-triangle body, 8 cameras, 512x512).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <glm/gtc/matrix_transform.hpp>
#include <string>
#include <vector>

#include "fvv/fvv_decoder.hpp"
#include "player/render/headless.h"
#include "player/render/renderer.h"

int main(int argc, char** argv) {
  std::string path;
  int width = 1280, height = 720, views = 60;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--size" && i + 1 < argc) {
      if (std::sscanf(argv[++i], "%dx%d", &width, &height) != 2) return 2;
    } else if (a == "--views" && i + 1 < argc) {
      views = std::atoi(argv[++i]);
    } else if (path.empty() && a[0] != '-') {
      path = a;
    } else {
      std::printf("usage: %s STREAM.fvv [--size WxH] [--views N]\n", argv[0]);
      return a == "-h" || a == "--help" ? 0 : 2;
    }
  }
  if (path.empty() || views < 1) {
    std::printf("usage: %s STREAM.fvv [--size WxH] [--views N]\n", argv[0]);
    return 2;
  }
  using Clock = std::chrono::steady_clock;
  const auto seconds = [](Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
  };
  fvv::DecoderPtr dec = fvv::MakeDecoder();
  if (fvv_decoder_open_file(dec.get(), path.c_str()) != FVV_OK) {
    std::fprintf(stderr, "render_bench: %s\n", fvv_decoder_error(dec.get()));
    return 1;
  }
  fvv_stream_info info;
  fvv_decoder_get_info(dec.get(), &info);
  fvv_model model;
  fvv_decoder_get_model(dec.get(), &model);
  fvv::FramePtr frame = fvv::DecodeFrame(dec.get(), 0, nullptr);
  if (!frame) return 1;
  auto ctx = fvv::HeadlessContext::Create(width, height);
  if (!ctx.ok()) {
    std::fprintf(stderr, "render_bench: %s\n", ctx.status().ToString().c_str());
    return 1;
  }
  const fvv::GlApi& gl = (*ctx)->gl();
  auto renderer = fvv::Renderer::Create(gl, model, fvv::DecoderCameras(dec.get()), info.atlas_width,
                                        info.atlas_height);
  if (!renderer.ok()) return 1;
  (*renderer)->MeasureDepthMaps(true);
  auto t = Clock::now();
  for (int i = 0; i < 8; ++i) {
    if (!(*renderer)->SetFrame(*frame).ok()) return 1;
  }
  gl.Finish();
  const double upload_ms = seconds(t) * 1e3 / 8;
  const glm::vec3 target(frame->bone_world[12], frame->bone_world[13], frame->bone_world[14]);
  const auto view_at = [&](int i) {
    fvv::RenderView v;
    const float angle = 6.2831853f * static_cast<float>(i) / static_cast<float>(views);
    v.eye = target + glm::vec3(3.5f * std::sin(angle), 0.4f, 3.5f * std::cos(angle));
    v.view = glm::lookAt(v.eye, target, glm::vec3(0, 1, 0));
    v.projection =
        glm::perspective(glm::radians(40.0f), float(width) / float(height), 0.05f, 50.0f);
    return v;
  };
  double draw_s = 1e30, read_s = 1e30;
  std::vector<uint8_t> rgb;
  for (int rep = 0; rep < 2; ++rep) {  // the faster of two runs
    t = Clock::now();
    for (int i = 0; i < views; ++i) {
      if (!(*renderer)->Draw(view_at(i), width, height).ok()) return 1;
      gl.Finish();
    }
    draw_s = std::min(draw_s, seconds(t));
    t = Clock::now();
    for (int i = 0; i < views; ++i) {
      if (!(*renderer)->Draw(view_at(i), width, height).ok()) return 1;
      if (!(*renderer)->ReadRgb(width, height, &rgb).ok()) return 1;
    }
    read_s = std::min(read_s, seconds(t));
  }
  std::printf("Renderer II on OSMesa, %dx%d, %u triangles, %u cameras of %ux%u, %d views:\n", width,
              height, model.triangle_count, info.camera_count, info.atlas_width, info.atlas_height,
              views);
  std::printf("  draw                 %7.1f fps (%.1f ms)\n", views / draw_s, draw_s * 1e3 / views);
  std::printf("  draw + read-back     %7.1f fps (%.1f ms)\n", views / read_s, read_s * 1e3 / views);
  std::printf("  texture upload       %7.1f ms per frame (every camera's texture%s)\n", upload_ms,
              info.has_masks ? " and mask" : "");
  if (!info.has_masks) {
    // Every view draws the depth maps of the cameras it blends that the frame
    // lacks; one frame's worth is what a view of it costs at most.
    const double per_layer = (*renderer)->depth_map_ms() /
                             double(std::max<uint64_t>(1, (*renderer)->depth_map_layers()));
    fvv::RenderView front = view_at(0);
    auto fresh = fvv::Renderer::Create(gl, model, fvv::DecoderCameras(dec.get()), info.atlas_width,
                                       info.atlas_height);
    if (fresh.ok()) (*fresh)->MeasureDepthMaps(true);
    if (!fresh.ok() || !(*fresh)->SetFrame(*frame).ok() ||
        !(*fresh)->Draw(front, width, height).ok()) {
      return 1;
    }
    std::printf(
        "  depth maps           %7.2f ms per camera; %.1f ms for the %llu cameras one view "
        "blends, %.1f ms for all %u\n",
        per_layer, (*fresh)->depth_map_ms(),
        static_cast<unsigned long long>((*fresh)->depth_map_layers()),
        per_layer * info.camera_count, info.camera_count);
  }
  return 0;
}
