// What a decoder holds for the largest GOP each level allows (SPEC.md 5): a
// stream of a few kilobytes declares the level's largest atlas and GOP (8
// frames x 8 cameras of the largest atlas side: the level's GOP samples), with
// empty texture streams, and is decoded through the C API in a child process
// (one frame as RGB8, as a player asks for it; one worker thread, no decode
// ahead). The child's peak resident memory, less that of a child that only
// opens the stream, is set against the bound SPEC.md 5 states.
//
//   build/bench/level_memory_bench [LEVEL ...]   (default 1 2 3; 4 needs ~17 GiB)
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "conformance/sample/sample_stream.h"
#include "container/file_header.h"
#include "container/writer.h"
#include "fvv/fvv_decoder.hpp"

namespace {

// The bound SPEC.md 5 states for one GOP: 16 bytes per GOP sample (three
// 32-bit channels, a byte of coder state per coefficient and channel, the
// RGB8 views of the frame asked for), the level's fragment bytes, 64 MiB.
double StatedBoundBytes(const fvv::LevelLimits& l) {
  return 16.0 * double(l.max_gop_samples) + double(l.max_fragment_bytes) + 64.0 * (1 << 20);
}

// The largest GOP of `level` as a stream file; false on an error (printed).
bool MakeLargestStream(const fvv::LevelLimits& l, const std::string& path) {
  fvv::SampleStreamOptions o;
  o.frames = 8;
  o.cameras = 8;
  o.gop_frames = 8;
  o.gop_cameras = 8;
  o.atlas_width = o.atlas_height = 8;
  o.masks = false;
  o.level = l.level;
  fvv::StatusOr<fvv::SampleStream> s = fvv::MakeSampleStream(o);
  if (!s.ok()) {
    std::fprintf(stderr, "level_memory_bench: %s\n", s.status().ToString().c_str());
    return false;
  }
  s->info.header.atlas_width = s->info.header.atlas_height = uint16_t(l.max_atlas_side);
  for (fvv::FragmentData& f : s->fragments) {
    for (fvv::ChannelStream& c : f.texture.channels) c = fvv::ChannelStream();
  }
  auto w = fvv::FileWriter::Create(path, s->info);
  if (!w.ok()) {
    std::fprintf(stderr, "level_memory_bench: %s\n", w.status().ToString().c_str());
    return false;
  }
  for (const auto& f : s->fragments) {
    if (fvv::Status st = (*w)->AddFragment(f); !st.ok()) {
      std::fprintf(stderr, "level_memory_bench: %s\n", st.ToString().c_str());
      return false;
    }
  }
  return (*w)->Close().ok();
}

// Runs `work` in a child; its peak resident set (bytes) and exit status.
template <typename F>
long ChildPeak(F work, int* status) {
  const pid_t pid = fork();
  if (pid == 0) _exit(work());
  struct rusage usage {};
  wait4(pid, status, 0, &usage);
  return usage.ru_maxrss * 1024L;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<int> levels;
  for (int i = 1; i < argc; ++i) {
    const int l = std::atoi(argv[i]);
    if (!fvv::FindLevel(uint8_t(l))) {
      std::fprintf(stderr,
                   "usage: %s [LEVEL ...] (levels 1..4; default 1 2 3, level 4 needs ~17 GiB)\n",
                   argv[0]);
      return 2;
    }
    levels.push_back(l);
  }
  if (levels.empty()) levels = {1, 2, 3};
  std::printf("%-6s %14s %12s %12s %14s %12s %10s %8s\n", "level", "GOP samples", "stream",
              "peak MiB", "bytes/sample", "bound MiB", "of bound", "seconds");
  for (int level : levels) {
    const fvv::LevelLimits& l = *fvv::FindLevel(uint8_t(level));
    const std::string path = "/tmp/fvv_level_memory_" + std::to_string(getpid()) + ".fvv";
    if (!MakeLargestStream(l, path)) return 1;
    FILE* f = std::fopen(path.c_str(), "rb");
    std::fseek(f, 0, SEEK_END);
    const long stream_bytes = std::ftell(f);
    std::fclose(f);
    const auto open = [&path](bool decode) {
      fvv_decoder_settings settings;
      fvv_decoder_default_settings(&settings);
      settings.threads = 1;
      settings.decode_ahead = 0;
      fvv::DecoderPtr dec = fvv::MakeDecoder(&settings);
      if (!dec || fvv_decoder_open_file(dec.get(), path.c_str()) != FVV_OK) return 3;
      if (!decode) return 0;
      fvv::FramePtr frame = fvv::DecodeFrame(dec.get(), 0, nullptr);
      if (!frame) {
        std::fprintf(stderr, "level_memory_bench: %s\n", fvv_decoder_error(dec.get()));
        return 4;
      }
      return frame->views[0].pixels ? 0 : 5;
    };
    int status = 0;
    const long base = ChildPeak([&] { return open(false); }, &status);
    const auto start = std::chrono::steady_clock::now();
    const long peak = ChildPeak([&] { return open(true); }, &status);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::remove(path.c_str());
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
      std::fprintf(stderr, "level_memory_bench: level %d: the decoding child failed (status %d)\n",
                   level, status);
      return 1;
    }
    const double used = double(peak - base), bound = StatedBoundBytes(l);
    std::printf("%-6d %14llu %12ld %12.0f %14.2f %12.0f %9.0f%% %8.1f\n", level,
                static_cast<unsigned long long>(l.max_gop_samples), stream_bytes, used / (1 << 20),
                used / double(l.max_gop_samples), bound / (1 << 20), 100 * used / bound, seconds);
    std::fflush(stdout);
  }
  return 0;
}
