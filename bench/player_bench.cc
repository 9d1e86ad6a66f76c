// Player benchmark (headless, OSMesa): a stream of 8 cameras at 25 fps is decoded
// and rendered at 1280x720 with full decodes, then decoding only the cameras the
// orbiting view blends (fvv_decode_budget.camera_mask, as fvv play does), then
// under forced time budgets of 1/2, 1/4, 1/8 and 1/16 of what a full GOP decode
// takes; reports the frame rate kept, the decode real-time factor, the PSNR of
// the decoded textures (used texels of the decoded cameras, against the source)
// and of the rendered image against the full decode's.
//
//   build/bench/player_bench [--atlas N] [--frames N] [--bpp B] [--gop-cameras N]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <glm/gtc/matrix_transform.hpp>
#include <string>

#include "codec/base/thread_pool.h"
#include "conformance/sample/sample_stream.h"
#include "container/writer.h"
#include "fvv/fvv_decoder.hpp"
#include "player/render/headless.h"
#include "player/render/renderer.h"

namespace {

using Clock = std::chrono::steady_clock;

double Seconds(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

struct Run {
  double fps = 0, psnr = 0, bytes_fraction = 0, gop_ms = 0, screen_psnr = 0, cameras = 0;
  std::vector<std::vector<uint8_t>> renders;  // kept for the full decode only
};

bool Play(const std::string& path, const fvv::SampleStream& src, double max_ms, bool view_cameras,
          const Run* reference, Run* out) {
  fvv::DecoderPtr dec = fvv::MakeDecoder();
  if (fvv_decoder_open_file(dec.get(), path.c_str()) != FVV_OK) return false;
  fvv_stream_info info;
  fvv_decoder_get_info(dec.get(), &info);
  auto ctx = fvv::HeadlessContext::Create(1280, 720);
  if (!ctx.ok()) {
    std::fprintf(stderr, "player_bench: %s\n", ctx.status().ToString().c_str());
    return false;
  }
  fvv_model model;
  fvv_decoder_get_model(dec.get(), &model);
  const std::vector<glm::vec3> centres = fvv::CameraCentres(dec.get());
  auto renderer = fvv::Renderer::Create((*ctx)->gl(), model, fvv::DecoderCameras(dec.get()),
                                        info.atlas_width, info.atlas_height);
  if (!renderer.ok()) return false;
  fvv_decode_budget budget{};
  budget.max_ms_per_gop = max_ms;
  const size_t texels = size_t{info.atlas_width} * info.atlas_height;
  double sq = 0, gop_ms = 0, screen_sq = 0, cameras = 0;
  size_t n = 0, screen_n = 0;
  uint64_t bytes = 0, available = 0;
  std::vector<uint8_t> rgb;
  const auto start = Clock::now();
  for (uint32_t f = 0; f < info.frame_count; ++f) {
    // The orbit of the view below; the cameras it blends are chosen as each GOP starts.
    const glm::vec3 offset(3.5f * std::sin(0.1f * f), 0.4f, 3.5f * std::cos(0.1f * f));
    if (view_cameras && f % info.gop_frames == 0) {
      const glm::vec3 centre(0.0f, 0.95f, 0.0f);  // the actor walks on the spot near here
      budget.camera_mask = fvv::ViewCameras(centres, centre + offset, centre);
    }
    fvv::FramePtr frame = fvv::DecodeFrame(dec.get(), f, &budget);
    if (!frame) return false;
    if (f % info.gop_frames == 0) {
      gop_ms += frame->report.decode_ms;
      bytes += frame->report.bytes_decoded;
      available += frame->report.bytes_available;
    }
    fvv::RenderView view;
    const glm::vec3 target(frame->bone_world[12], frame->bone_world[13], frame->bone_world[14]);
    view.eye = target + offset;
    view.view = glm::lookAt(view.eye, target, glm::vec3(0, 1, 0));
    view.projection = glm::perspective(glm::radians(40.0f), 1280.0f / 720.0f, 0.05f, 50.0f);
    if (!(*renderer)->SetFrame(*frame).ok() || !(*renderer)->Draw(view, 1280, 720).ok() ||
        !(*renderer)->ReadRgb(1280, 720, &rgb).ok()) {
      return false;
    }
    if (reference) {
      const std::vector<uint8_t>& ref = reference->renders[f];
      for (size_t i = 0; i < rgb.size(); ++i) {
        const double d = double(rgb[i]) - ref[i];
        screen_sq += d * d;
      }
      screen_n += rgb.size();
    } else {
      out->renders.push_back(rgb);
    }
    for (uint32_t c = 0; c < info.camera_count; ++c) {  // PSNR over used texels (cheap)
      if (!frame->views[c].pixels) continue;            // a camera left out
      cameras += 1.0 / info.frame_count;
      const size_t plane = size_t{f} * info.camera_count + c;
      for (size_t i = 0; i < texels; ++i) {
        if (!src.masks[plane * texels + i]) continue;
        for (int k = 0; k < 3; ++k) {
          const double d =
              double(frame->views[c].pixels[3 * i + k]) - src.rgb[(plane * texels + i) * 3 + k];
          sq += d * d;
          ++n;
        }
      }
    }
  }
  const double elapsed = Seconds(start);
  out->fps = info.frame_count / elapsed;
  out->psnr = 10 * std::log10(255.0 * 255.0 / std::max(1e-9, sq / double(n)));
  out->bytes_fraction = available ? double(bytes) / available : 1;
  out->gop_ms = gop_ms / ((info.frame_count + info.gop_frames - 1) / info.gop_frames);
  out->screen_psnr =
      screen_n ? 10 * std::log10(255.0 * 255.0 / std::max(1e-9, screen_sq / double(screen_n)))
               : 99.0;
  out->cameras = cameras;
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  fvv::SampleStreamOptions o;
  o.frames = 32;
  o.cameras = 8;
  o.atlas_width = o.atlas_height = 256;
  o.bpp = 0.25;
  o.gop_cameras = 1;  // the encoder's default: one camera per fragment
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--atlas" && i + 1 < argc) {
      o.atlas_width = o.atlas_height = static_cast<uint16_t>(std::atoi(argv[++i]));
    } else if (a == "--frames" && i + 1 < argc) {
      o.frames = static_cast<uint32_t>(std::atoi(argv[++i]));
    } else if (a == "--bpp" && i + 1 < argc) {
      o.bpp = std::atof(argv[++i]);
    } else if (a == "--gop-cameras" && i + 1 < argc) {
      o.gop_cameras = static_cast<uint16_t>(std::atoi(argv[++i]));
    } else {
      std::printf("usage: %s [--atlas N] [--frames N] [--bpp B] [--gop-cameras N]\n", argv[0]);
      return a == "-h" || a == "--help" ? 0 : 2;
    }
  }
  fvv::ThreadPool pool(2);
  auto sample = fvv::MakeSampleStream(o, pool.runner());
  if (!sample.ok()) return 1;
  const std::string path = "/tmp/fvv_player_bench.fvv";
  auto w = fvv::FileWriter::Create(path, sample->info);
  if (!w.ok()) return 1;
  for (const auto& f : sample->fragments) {
    if (!(*w)->AddFragment(f).ok()) return 1;
  }
  if (!(*w)->Close().ok()) return 1;
  std::printf(
      "player, headless (OSMesa) at 1280x720: %u frames x %u cameras x %ux%u at 25 fps, "
      "%.2f bpp, GOP 8 frames x %u cameras; decode + upload + render + read-back per frame, "
      "sequential\n",
      o.frames, o.cameras, o.atlas_width, o.atlas_height, o.bpp, unsigned{o.gop_cameras});
  const double gop_play_ms = 8 * 1000.0 / 25;
  std::printf("%-28s %7s %8s %8s %8s %9s %11s %9s\n", "mode", "fps", "ms/GOP", "RTF", "cameras",
              "bytes", "texture dB", "screen dB");
  const auto row = [&](const std::string& mode, const Run& r) {
    std::printf("%-28s %7.1f %8.0f %8.2f %8.1f %8.0f%% %11.2f %9.2f\n", mode.c_str(), r.fps,
                r.gop_ms, r.gop_ms / gop_play_ms, r.cameras, 100 * r.bytes_fraction, r.psnr,
                r.screen_psnr);
  };
  Run full;
  if (!Play(path, *sample, 0, false, nullptr, &full)) return 1;
  row("full decode", full);
  Run view;
  if (!Play(path, *sample, 0, true, &full, &view)) return 1;
  row("cameras the view blends", view);
  // The time budget bounds the SPIHT stage only (transform and output are fixed
  // costs), so budgets go well below half of the full decode time.
  for (int div : {2, 4, 8, 16}) {
    Run cut;
    const double budget = full.gop_ms / div;
    if (!Play(path, *sample, budget, false, &full, &cut)) return 1;
    row("budget " + std::to_string(int(budget)) + " ms/GOP (1/" + std::to_string(div) + ")", cut);
  }
  std::remove(path.c_str());
  return 0;
}
