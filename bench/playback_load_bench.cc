// The real-time player on a busy machine (headless, OSMesa): the playback loop
// of `fvv play` runs a stream for S seconds at a 60 Hz display's pace (drawing
// when the frame changes, as `fvv play` does while the view is still) while
// stress-ng keeps 0, 1 and 2 cores busy, then through a load step (idle, 2
// cores busy, idle). Per condition: fps drawn, playback speed against real
// time, share of texture bytes decoded, PSNR over the actor's pixels of every
// frame shown against the same frame and view rendered from the fully decoded
// stream (minimum and mean), stalls (a frame on screen for more than 2 frame
// times) and frames shown without a texture byte. The load step's timeline
// goes to a CSV (bench/run_playback_load_bench.sh plots it).
//
//   build/bench/playback_load_bench STREAM [--seconds S] [--floor F] [--csv FILE]
//                                   [--only floors|idle|1|2|2nofloor|step]
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <glm/gtc/matrix_transform.hpp>
#include <string>
#include <thread>
#include <vector>

#include "fvv/fvv_decoder.hpp"
#include "player/playback/playback_loop.h"
#include "player/render/headless.h"
#include "player/render/renderer.h"

namespace {

using Clock = std::chrono::steady_clock;
constexpr int kWidth = 1280, kHeight = 720;
constexpr double kDisplayHz = 60;

double Since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

// The view of frame f: a swing of +-30 degrees around the actor once per loop
// of the stream (90 degrees a second at its fastest), a function of the frame
// only, so that the reference render of a frame has the same view.
fvv::RenderView ViewOf(const fvv_frame& frame, uint32_t f, uint32_t frames) {
  fvv::RenderView view;
  const glm::vec3 target(frame.bone_world[12], frame.bone_world[13], frame.bone_world[14]);
  const float a = 0.52f * std::sin(6.2831853f * float(f) / float(frames));
  view.eye = target + glm::vec3(3.2f * std::sin(a), 0.4f, 3.2f * std::cos(a));
  view.view = glm::lookAt(view.eye, target, glm::vec3(0, 1, 0));
  view.projection =
      glm::perspective(glm::radians(40.0f), float(kWidth) / float(kHeight), 0.05f, 50.0f);
  return view;
}

// stress-ng keeping `cores` cores busy; killed (and its workers with it) by Stop
// or when this process dies.
class Load {
 public:
  explicit Load(int cores) {
    if (cores <= 0) return;
    pid_ = fork();
    if (pid_ == 0) {
      prctl(PR_SET_PDEATHSIG, SIGTERM);
      const std::string n = std::to_string(cores);
      execlp("stress-ng", "stress-ng", "--cpu", n.c_str(), "--cpu-method", "int64", "--timeout",
             "300s", "--quiet", static_cast<char*>(nullptr));
      std::perror("playback_load_bench: stress-ng (tools/setup.sh installs it)");
      _exit(127);
    }
  }
  ~Load() { Stop(); }
  void Stop() {
    if (pid_ <= 0) return;
    kill(pid_, SIGTERM);
    int status = 0;
    waitpid(pid_, &status, 0);
    pid_ = -1;
  }

 private:
  pid_t pid_ = -1;
};

// Every frame rendered from the whole stream, and which pixels are the actor's.
struct Reference {
  std::vector<std::vector<uint8_t>> rgb;
  std::vector<std::vector<uint8_t>> actor;
  glm::vec3 eye0{0.0f}, target0{0.0f};  // frame 0's view, the player's first
};

bool MakeReference(const std::string& path, fvv::Renderer* renderer, Reference* ref) {
  fvv::DecoderPtr dec = fvv::MakeDecoder();
  if (fvv_decoder_open_file(dec.get(), path.c_str()) != FVV_OK) return false;
  fvv_stream_info info;
  fvv_decoder_get_info(dec.get(), &info);
  std::vector<uint8_t> other;
  for (uint32_t f = 0; f < info.frame_count; ++f) {
    fvv::FramePtr frame = fvv::DecodeFrame(dec.get(), f, nullptr);
    if (!frame || !renderer->SetFrame(*frame).ok()) return false;
    fvv::RenderView view = ViewOf(*frame, f, info.frame_count);
    if (f == 0) {
      ref->eye0 = view.eye;
      ref->target0 = glm::vec3(frame->bone_world[12], frame->bone_world[13], frame->bone_world[14]);
    }
    ref->rgb.emplace_back();
    if (!renderer->Draw(view, kWidth, kHeight).ok() ||
        !renderer->ReadRgb(kWidth, kHeight, &ref->rgb.back()).ok()) {
      return false;
    }
    // The actor's pixels: those that do not change with the background colour.
    view.background = glm::vec3(0.9f, 0.1f, 0.6f);
    if (!renderer->Draw(view, kWidth, kHeight).ok() ||
        !renderer->ReadRgb(kWidth, kHeight, &other).ok()) {
      return false;
    }
    std::vector<uint8_t>& actor = ref->actor.emplace_back(size_t{kWidth} * kHeight);
    for (size_t i = 0; i < actor.size(); ++i) {
      actor[i] = ref->rgb.back()[3 * i] == other[3 * i] &&
                 ref->rgb.back()[3 * i + 1] == other[3 * i + 1] &&
                 ref->rgb.back()[3 * i + 2] == other[3 * i + 2];
    }
  }
  return true;
}

double ActorPsnr(const std::vector<uint8_t>& rgb, const Reference& ref, uint32_t f) {
  double sq = 0;
  size_t n = 0;
  for (size_t i = 0; i < ref.actor[f].size(); ++i) {
    if (!ref.actor[f][i]) continue;
    for (int k = 0; k < 3; ++k) {
      const double d = double(rgb[3 * i + k]) - ref.rgb[f][3 * i + k];
      sq += d * d;
    }
    n += 3;
  }
  return n ? 10 * std::log10(255.0 * 255.0 / std::max(1e-3, sq / double(n))) : 99.0;
}

struct Sample {  // one shown frame of a run
  double t, budget_ms, share, fps, psnr;
  int load;
  uint32_t frame;
};

struct Result {
  double fps = 0, speed = 0, share = 0, min_psnr = 99, mean_psnr = 0, seconds = 0;
  double cameras = 0;  // decoded, mean over the frames drawn
  uint64_t stalls = 0, untextured = 0, frames = 0;
  std::vector<Sample> samples;
};

// Plays for `seconds` with the load `load_at(t)` asks for (cores busy).
template <typename LoadAt>
bool Play(const std::string& path, double floor_share, double seconds, LoadAt load_at,
          fvv::Renderer* renderer, const Reference& ref, Result* out) {
  fvv::DecoderPtr dec = fvv::MakeDecoder();
  if (fvv_decoder_open_file(dec.get(), path.c_str()) != FVV_OK) return false;
  fvv_stream_info info;
  fvv_decoder_get_info(dec.get(), &info);
  fvv::DecoderFrameSource source(dec.get());
  fvv::PlaybackLoop loop(&source, info, fvv::CameraCentres(dec.get()), floor_share);
  const double fps = double(info.frame_rate_num) / info.frame_rate_den;
  std::vector<uint8_t> rgb;
  int cores = -1;
  std::unique_ptr<Load> load;
  const auto start = Clock::now();
  auto last = start, tick = start;
  glm::vec3 eye = ref.eye0, target = ref.target0;
  std::vector<double> drawn_at;  // for the fps of the last half second
  double psnr_sum = 0;
  for (;;) {
    const double t = Since(start);
    if (t >= seconds) break;
    if (load_at(t) != cores) {
      cores = load_at(t);
      load.reset();
      load = std::make_unique<Load>(cores);
    }
    const auto now = Clock::now();
    const double dt = std::chrono::duration<double>(now - last).count();
    last = now;
    const fvv::Status advanced = loop.Advance(dt, eye, target);
    if (!advanced.ok()) {
      std::fprintf(stderr, "playback_load_bench: %s\n", advanced.ToString().c_str());
      return false;
    }
    const fvv_frame* frame = source.frame();
    const uint32_t f = loop.frame_index();
    const fvv::RenderView view = ViewOf(*frame, f, info.frame_count);
    eye = view.eye;
    target = glm::vec3(frame->bone_world[12], frame->bone_world[13], frame->bone_world[14]);
    if (!loop.frame_changed()) {  // nothing new to draw: wait for the next refresh
      tick += std::chrono::microseconds(static_cast<int64_t>(1e6 / kDisplayHz));
      if (tick < Clock::now()) tick = Clock::now();
      std::this_thread::sleep_until(tick);
      continue;
    }
    const auto r0 = Clock::now();
    if (!renderer->SetFrame(*frame).ok()) return false;
    if (!renderer->Draw(view, kWidth, kHeight).ok()) return false;
    if (!renderer->ReadRgb(kWidth, kHeight, &rgb).ok()) return false;  // the display's copy
    loop.FrameDrawn(std::chrono::duration<double, std::milli>(Clock::now() - r0).count());
    drawn_at.push_back(t);
    {
      const double psnr = ActorPsnr(rgb, ref, f);
      out->min_psnr = std::min(out->min_psnr, psnr);
      psnr_sum += psnr;
      out->cameras += source.CamerasTaken();
      ++out->frames;
      size_t recent = 0;
      for (auto it = drawn_at.rbegin(); it != drawn_at.rend() && *it > t - 0.5; ++it) ++recent;
      const fvv_decode_report& r = frame->report;
      out->samples.push_back({t, loop.controller().NextMaxMs(),
                              r.bytes_available ? double(r.bytes_decoded) / r.bytes_available : 1.0,
                              recent / std::min(0.5, std::max(1e-3, t)), psnr, cores, f});
    }
    // A 60 Hz display: the next frame at the next refresh.
    tick += std::chrono::microseconds(static_cast<int64_t>(1e6 / kDisplayHz));
    if (tick < Clock::now()) tick = Clock::now();
    std::this_thread::sleep_until(tick);
  }
  load.reset();
  const fvv::PlaybackStats& st = loop.stats();
  out->seconds = Since(start);
  out->fps = st.frames_drawn / out->seconds;
  out->speed = st.frames_advanced / (out->seconds * fps);
  out->share = st.bytes_available ? double(st.bytes_decoded) / st.bytes_available : 1.0;
  out->stalls = st.stalls;
  out->untextured = st.frames_without_texture;
  out->mean_psnr = out->frames ? psnr_sum / out->frames : 0;
  out->cameras = out->frames ? out->cameras / out->frames : 0;
  return true;
}

// What a floor alone gives: every frame decoded with a time budget that runs out
// at once, so exactly the floor's share of each stream is read; the actor's
// PSNR against the whole decode (minimum and mean over frames) and the decode
// time per GOP on an idle machine.
bool FloorRow(const std::string& path, double share, fvv::Renderer* renderer,
              const Reference& ref) {
  fvv::DecoderPtr dec = fvv::MakeDecoder();
  if (fvv_decoder_open_file(dec.get(), path.c_str()) != FVV_OK) return false;
  fvv_stream_info info;
  fvv_decoder_get_info(dec.get(), &info);
  fvv_decode_budget budget{};
  budget.max_ms_per_gop = 1e-3;
  budget.floor_share = share;
  double min_psnr = 99, sum = 0, gop_ms = 0, bytes = 0, available = 0;
  std::vector<uint8_t> rgb;
  for (uint32_t f = 0; f < info.frame_count; ++f) {
    fvv::FramePtr frame = fvv::DecodeFrame(dec.get(), f, &budget);
    if (!frame || !renderer->SetFrame(*frame).ok()) return false;
    if (f % info.gop_frames == 0) {
      gop_ms += frame->report.decode_ms;
      bytes += frame->report.bytes_decoded;
      available += frame->report.bytes_available;
    }
    if (!renderer->Draw(ViewOf(*frame, f, info.frame_count), kWidth, kHeight).ok() ||
        !renderer->ReadRgb(kWidth, kHeight, &rgb).ok()) {
      return false;
    }
    const double psnr = ActorPsnr(rgb, ref, f);
    min_psnr = std::min(min_psnr, psnr);
    sum += psnr;
  }
  const uint32_t gops = (info.frame_count + info.gop_frames - 1) / info.gop_frames;
  std::printf("floor %4.0f%%  %7.1f%% %9.2f %9.2f %9.0f\n", 100 * share, 100 * bytes / available,
              min_psnr, sum / info.frame_count, gop_ms / gops);
  return true;
}

void PrintRow(const std::string& name, const Result& r) {
  std::printf("%-22s %6.1f %7.2fx %7.1f%% %8.1f %9.2f %9.2f %7llu %10llu\n", name.c_str(), r.fps,
              r.speed, 100 * r.share, r.cameras, r.min_psnr, r.mean_psnr,
              static_cast<unsigned long long>(r.stalls),
              static_cast<unsigned long long>(r.untextured));
}

bool WriteCsv(const std::string& path, const Result& r, double load_on, double load_off) {
  const std::string tmp = path + ".tmp";
  FILE* f = std::fopen(tmp.c_str(), "w");
  if (!f) return false;
  std::fprintf(f, "# load step: 2 cores busy from %.2f s to %.2f s\n", load_on, load_off);
  std::fprintf(f, "t_s,cores_busy,frame,budget_ms,bytes_share,fps,psnr_db\n");
  for (const Sample& s : r.samples) {
    std::fprintf(f, "%.3f,%d,%u,%.1f,%.4f,%.1f,%.2f\n", s.t, s.load, s.frame, s.budget_ms, s.share,
                 s.fps, s.psnr);
  }
  const bool ok = std::fclose(f) == 0;
  return ok && std::rename(tmp.c_str(), path.c_str()) == 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::string path, csv, only;
  double seconds = 20, floor_share = fvv::PlaybackController::kDefaultFloorShare;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--seconds" && i + 1 < argc) {
      seconds = std::atof(argv[++i]);
    } else if (a == "--floor" && i + 1 < argc) {
      floor_share = std::atof(argv[++i]);
    } else if (a == "--csv" && i + 1 < argc) {
      csv = argv[++i];
    } else if (a == "--only" && i + 1 < argc) {
      only = argv[++i];
    } else if (a[0] != '-' && path.empty()) {
      path = a;
    } else {
      std::printf(
          "usage: %s STREAM [--seconds S] [--floor F] [--csv FILE] [--only "
          "floors|idle|1|2|2nofloor|step]\n",
          argv[0]);
      return a == "-h" || a == "--help" ? 0 : 2;
    }
  }
  if (path.empty() || !(seconds > 1) || !(floor_share >= 0 && floor_share <= 1)) {
    std::fprintf(stderr, "playback_load_bench: a stream, seconds > 1 and a floor in 0..1\n");
    return 2;
  }
  auto ctx = fvv::HeadlessContext::Create(kWidth, kHeight);
  if (!ctx.ok()) {
    std::fprintf(stderr, "playback_load_bench: %s\n", ctx.status().ToString().c_str());
    return 1;
  }
  fvv::DecoderPtr dec = fvv::MakeDecoder();
  if (fvv_decoder_open_file(dec.get(), path.c_str()) != FVV_OK) {
    std::fprintf(stderr, "playback_load_bench: %s\n", fvv_decoder_error(dec.get()));
    return 1;
  }
  fvv_stream_info info;
  fvv_decoder_get_info(dec.get(), &info);
  fvv_model model;
  fvv_decoder_get_model(dec.get(), &model);
  auto renderer = fvv::Renderer::Create((*ctx)->gl(), model, fvv::DecoderCameras(dec.get()),
                                        info.atlas_width, info.atlas_height);
  if (!renderer.ok()) return 1;
  Reference ref;
  if (!MakeReference(path, renderer->get(), &ref)) return 1;
  std::printf(
      "playback under load, headless (OSMesa) at %dx%d, %.0f Hz display: %s, %u frames x %u "
      "cameras, atlas %ux%u, GOP %u frames; floor %.0f%% of each texture stream; %.0f s per "
      "condition; load from stress-ng --cpu N\n",
      kWidth, kHeight, kDisplayHz, path.c_str(), info.frame_count, info.camera_count,
      info.atlas_width, info.atlas_height, info.gop_frames, 100 * floor_share, seconds);
  if (only.empty() || only == "floors") {
    std::printf("%-11s %8s %9s %9s %9s\n", "floor only", "bytes", "min dB", "mean dB", "ms/GOP");
    for (double share : {0.05, 0.1, 0.15, 0.2, 0.3}) {
      if (!FloorRow(path, share, renderer->get(), ref)) return 1;
    }
  }
  std::printf("%-22s %6s %8s %8s %8s %9s %9s %7s %10s\n", "condition", "fps", "speed", "bytes",
              "cameras", "min dB", "mean dB", "stalls", "untextured");
  // The last row is the peer: the same controller without a floor, under the
  // heaviest load.
  const struct {
    int cores;
    double floor;
    const char *name, *label;
  } conditions[] = {{0, floor_share, "idle", "idle"},
                    {1, floor_share, "1", "1 core busy"},
                    {2, floor_share, "2", "2 cores busy"},
                    {2, 0.0, "2nofloor", "2 busy, no floor"}};
  for (const auto& c : conditions) {
    if (!only.empty() && only != c.name) continue;
    Result r;
    const int cores = c.cores;
    if (!Play(
            path, c.floor, seconds, [cores](double) { return cores; }, renderer->get(), ref, &r)) {
      return 1;
    }
    PrintRow(c.label, r);
  }
  if (only.empty() || only == "step") {
    const double on = 0.25 * seconds, off = 0.75 * seconds;
    Result r;
    if (!Play(
            path, floor_share, seconds, [on, off](double t) { return t >= on && t < off ? 2 : 0; },
            renderer->get(), ref, &r)) {
      return 1;
    }
    PrintRow("step idle/2/idle", r);
    // Quality back: the idle share is that of the GOPs shown in the idle lead-in
    // after its first second; recovery is the time from the load's end to the
    // first frame whose GOP has 90 % of it.
    double idle_sum = 0;
    int idle_n = 0;
    for (const Sample& s : r.samples) {
      if (s.t >= 1 && s.t < on) idle_sum += s.share, ++idle_n;
    }
    const double idle_share = idle_n ? idle_sum / idle_n : 1;
    double recovered = -1, loaded_min = 1;
    for (const Sample& s : r.samples) {
      if (s.t >= on && s.t < off) loaded_min = std::min(loaded_min, s.share);
      if (s.t >= off && recovered < 0 && s.share >= 0.9 * idle_share) recovered = s.t - off;
    }
    std::printf(
        "load step: idle share %.1f%%, lowest share under load %.1f%%, back to 90%% of the idle "
        "share %s after the load ended\n",
        100 * idle_share, 100 * loaded_min,
        recovered < 0 ? "never"
                      : (std::to_string(int(std::lround(1000 * recovered))) + " ms").c_str());
    if (!csv.empty() && !WriteCsv(csv, r, on, off)) {
      std::fprintf(stderr, "playback_load_bench: cannot write %s\n", csv.c_str());
      return 1;
    }
  }
  return 0;
}
