// Decoder-library benchmark: decode Msamples/s and real-time factor (decode time /
// play time) through the C API, for a stream of 8 cameras x 512x512 at 25 fps at
// four rates, with frames delivered as RGB8 (what a player uploads).
//
//   build/bench/decoder_bench [--frames N] [--gop-cameras N] [--masks mixing|context|both]
//                             [--stream FILE] [--yuv]
//
// Each rate is coded once per mask mode (default both: mode 2 "mixing", what
// `fvv encode` writes, and mode 1 "context"). 48 frames (6 GOP spans) by default:
// the decoder recycles a dropped GOP's buffers, so the first two spans of a
// stream are slower than the steady state a player runs in.
//
// --stream FILE times the decoding of an existing stream (e.g. the demo's
// out/demo/capture.fvv) instead of the synthetic ones; --yuv asks for planar
// YUV 4:4:4 (what a player converting colour on the GPU uploads) instead of RGB8.
//
// --gop-cameras 1 (the encoder's default) codes each camera's atlas sequence as
// its own fragment; 8 puts all cameras of a time span in one 4D block.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "codec/base/thread_pool.h"
#include "conformance/sample/sample_stream.h"
#include "container/writer.h"
#include "fvv/fvv_decoder.hpp"

namespace {

fvv_decode_budget g_budget{};  // whole streams, in the format --yuv picks

// Decodes every frame of the stream at `path` through the C API, twice, and
// returns the faster run's seconds (negative on an error, printed); `info` and
// `bytes` (texture bytes of every GOP) describe the stream.
double BestDecodeSeconds(const std::string& path, fvv_stream_info* info, uint64_t* bytes) {
  using Clock = std::chrono::steady_clock;
  double best = 1e30;
  for (int rep = 0; rep < 2; ++rep) {
    fvv_decoder_settings s;
    fvv_decoder_default_settings(&s);
    s.threads = 2;
    fvv::DecoderPtr dec = fvv::MakeDecoder(&s);
    if (fvv_decoder_open_file(dec.get(), path.c_str()) != FVV_OK) {
      std::fprintf(stderr, "decoder_bench: %s\n", fvv_decoder_error(dec.get()));
      return -1;
    }
    fvv_decoder_get_info(dec.get(), info);
    *bytes = 0;
    const auto t0 = Clock::now();
    for (uint32_t f = 0; f < info->frame_count; ++f) {
      fvv::FramePtr frame = fvv::DecodeFrame(dec.get(), f, &g_budget);
      if (!frame) {
        std::fprintf(stderr, "decoder_bench: %s\n", fvv_decoder_error(dec.get()));
        return -1;
      }
      if (f % info->gop_frames == 0) *bytes += frame->report.bytes_available;
    }
    best = std::min(best, std::chrono::duration<double>(Clock::now() - t0).count());
  }
  return best;
}

// Times an existing stream.
int TimeStream(const std::string& path) {
  fvv_stream_info info{};
  uint64_t bytes = 0;
  const double best = BestDecodeSeconds(path, &info, &bytes);
  if (best < 0) return 1;
  const double play = info.frame_count * double(info.frame_rate_den) / info.frame_rate_num;
  const double samples =
      double(info.frame_count) * info.camera_count * info.atlas_width * info.atlas_height;
  std::printf(
      "%s: %u frames x %u cameras x %ux%u, GOP %u frames x %u cameras, %llu texture "
      "bytes (%.3f bpp)\n",
      path.c_str(), info.frame_count, info.camera_count, info.atlas_width, info.atlas_height,
      info.gop_frames, info.gop_cameras, static_cast<unsigned long long>(bytes),
      8.0 * bytes / samples);
  std::printf("decode %.0f ms for %.2f s of video: %.1f Msamples/s, real-time factor %.2f\n",
              best * 1e3, play, samples / best / 1e6, best / play);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  uint32_t frames = 48;
  uint16_t gop_cameras = 1;
  std::string stream, masks = "both";
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--frames" && i + 1 < argc) {
      frames = static_cast<uint32_t>(std::atoi(argv[++i]));
    } else if (a == "--yuv") {
      g_budget.format = FVV_FORMAT_YUV444;
    } else if (a == "--stream" && i + 1 < argc) {
      stream = argv[++i];
    } else if (a == "--gop-cameras" && i + 1 < argc) {
      gop_cameras = static_cast<uint16_t>(std::atoi(argv[++i]));
    } else if (a == "--masks" && i + 1 < argc &&
               (std::string(argv[i + 1]) == "mixing" || std::string(argv[i + 1]) == "context" ||
                std::string(argv[i + 1]) == "both")) {
      masks = argv[++i];
    } else {
      std::printf(
          "usage: %s [--frames N] [--gop-cameras N] [--masks mixing|context|both] [--stream FILE] "
          "[--yuv]\n",
          argv[0]);
      return a == "-h" || a == "--help" ? 0 : 2;
    }
  }
  if (!stream.empty()) return TimeStream(stream);
  fvv::ThreadPool pool(2);
  std::printf(
      "decoder library, %u frames x 8 cameras x 512x512 at 25 fps, GOP 8 frames x %u cameras, "
      "9/7 + arith, masks, 2 threads, %s output\n",
      frames, unsigned{gop_cameras}, g_budget.format == FVV_FORMAT_YUV444 ? "YUV444" : "RGB8");
  std::printf("%-8s %6s %10s %10s %12s %10s %12s\n", "masks", "bpp", "bytes", "decode ms",
              "ms per GOP", "Msamples/s", "real-time f.");
  std::vector<fvv::MaskCoding> modes;
  if (masks != "context") modes.push_back(fvv::MaskCoding::kMixing);
  if (masks != "mixing") modes.push_back(fvv::MaskCoding::kContext);
  for (double bpp : {0.05, 0.1, 0.25, 0.5}) {
    for (fvv::MaskCoding mode : modes) {
      fvv::SampleStreamOptions o;
      o.frames = frames;
      o.cameras = 8;
      o.atlas_width = o.atlas_height = 512;
      o.gop_cameras = gop_cameras;
      o.bpp = bpp;
      o.mask_coding = mode;
      auto sample = fvv::MakeSampleStream(o, pool.runner());
      if (!sample.ok()) {
        std::fprintf(stderr, "decoder_bench: %s\n", sample.status().ToString().c_str());
        return 1;
      }
      const std::string path = "/tmp/fvv_decoder_bench_" + std::to_string(getpid()) + ".fvv";
      auto w = fvv::FileWriter::Create(path, sample->info);
      if (!w.ok()) return 1;
      for (const auto& f : sample->fragments) {
        if (!(*w)->AddFragment(f).ok()) return 1;
      }
      if (!(*w)->Close().ok()) return 1;
      fvv_stream_info info{};
      uint64_t decoded_bytes = 0;
      const double best = BestDecodeSeconds(path, &info, &decoded_bytes);
      std::remove(path.c_str());
      if (best < 0) return 1;
      const double samples = double(frames) * 8 * 512 * 512;
      uint64_t bytes = 0;
      for (const auto& f : sample->fragments) bytes += f.texture.total_bytes();
      std::printf("%-8s %6.2f %10llu %10.0f %12.0f %10.1f %12.2f\n",
                  mode == fvv::MaskCoding::kMixing ? "mixing" : "context", bpp,
                  static_cast<unsigned long long>(bytes), best * 1e3, best * 1e3 / (frames / 8.0),
                  samples / best / 1e6, best / (frames / 25.0));
      std::fflush(stdout);
    }
  }
  return 0;
}
