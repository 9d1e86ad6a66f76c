// The surface of every frame against today's encoder on a synthetic actor in
// loose shorts (`fvv synth --garment`), measured as a user's take would be: the
// poses tracked (`fvv track`), not given; the encoder of before with the
// fitted proportions and the first frame's shape refinement (--refine-shape),
// against the stream with the surface of every frame (--surface), at the
// default rate and, for the views, at the same total bytes (the plain stream
// re-coded at the surface stream's size). Per stream: the true surface's mean
// distance to the surface a player draws (over the whole body, and where the
// garment stands off the plain stream's body by more than 1 cm), and Renderer
// II's PSNR over the actor in the held-out cameras (mean over cameras and
// frames). One table; bench/README.md.
// Usage: garment_bench [--out DIR] [--frames N] [--cameras N] [--width W --height H]
//                      [--garment M] [--true-silhouettes 0|1] [--reuse 0|1]
//                      [--quick 0|1] [--true-poses 0|1] [--persons 0|1] and the surface tracker's
//                      weights: [--prior W] [--temporal W] [--smoothness W] [--spread N]
//                      [--steps N] [--stereo W] [--stereo-neighbours N]
//                      [--stereo-ncc C] [--stereo-angle RAD] [--stereo-every N]
// --reuse 1 takes the capture and poses an earlier run left in DIR; --quick 1
// encodes only the first two streams (no equal-bytes one): for trying weights;
// --true-poses 1 encodes with the true poses instead of the tracked ones;
// --persons 1 tracks as on real footage, with the person network's masks and
// keypoints (the encoder's silhouettes stay the background subtraction's).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "encoder/encode/encoder.h"
#include "encoder/track/track_capture.h"
#include "tools/synth/surface_distance.h"
#include "tools/synth/synth.h"
#include "tools/synth/view_score.h"

namespace {

struct Scored {
  std::string name;
  uint64_t bytes = 0, surface_bytes = 0;
  double whole_mm = 0, off_mm = 0, psnr = 0;
};

// The true vertices standing off the plain stream's body (> 1 cm), per frame.
using StandOff = std::vector<std::vector<bool>>;

// `dist`: DistanceToTrueSurface of `stream`.
fvv::Status Score(const std::string& stream, const std::vector<std::vector<double>>& dist,
                  const fvv::SynthOptions& so, const StandOff& off, Scored* s) {
  double whole = 0, standing = 0;
  size_t n = 0, m = 0;
  for (size_t f = 0; f < dist.size(); ++f) {
    for (size_t v = 0; v < dist[f].size(); ++v) {
      whole += dist[f][v], ++n;
      if (f < off.size() && v < off[f].size() && off[f][v]) standing += dist[f][v], ++m;
    }
  }
  s->whole_mm = n ? 1000 * whole / n : 0;
  s->off_mm = m ? 1000 * standing / m : 0;
  double psnr = 0;
  for (uint32_t c = 0; c < so.held_out; ++c) {
    for (uint32_t f = 0; f < so.frames; ++f) {
      FVV_ASSIGN_OR_RETURN(const double p, fvv::HeldOutStreamPsnr(stream, so.output_dir, c, f));
      psnr += p;
    }
  }
  s->psnr = psnr / (so.held_out * so.frames);
  return fvv::Status::Ok();
}

int Fail(const std::string& what, const fvv::Status& s) {
  std::fprintf(stderr, "garment_bench: %s: %s\n", what.c_str(), s.ToString().c_str());
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  std::string out = "out/garment_bench";
  fvv::SynthOptions so;
  so.cameras = 8;
  so.frames = 16;
  so.width = 320;
  so.height = 240;
  so.held_out = 2;
  so.garment = 0.08;
  bool reuse = false, quick = false, true_poses = false, persons = false;
  fvv::SurfaceTrackingOptions tracking;
  for (int i = 1; i < argc; i += 2) {
    const std::string a = i + 1 < argc ? argv[i] : "--help";
    const char* v = i + 1 < argc ? argv[i + 1] : "";
    if (a == "--out") {
      out = v;
    } else if (a == "--frames") {
      so.frames = uint32_t(std::atoi(v));
    } else if (a == "--cameras") {
      so.cameras = uint32_t(std::atoi(v));
    } else if (a == "--width") {
      so.width = uint32_t(std::atoi(v));
    } else if (a == "--height") {
      so.height = uint32_t(std::atoi(v));
    } else if (a == "--garment") {
      so.garment = std::atof(v);
    } else if (a == "--true-silhouettes") {
      so.link_silhouettes = std::atoi(v) != 0;
    } else if (a == "--reuse") {
      reuse = std::atoi(v) != 0;
    } else if (a == "--quick") {
      quick = std::atoi(v) != 0;
    } else if (a == "--persons") {
      persons = std::atoi(v) != 0;
    } else if (a == "--true-poses") {
      true_poses = std::atoi(v) != 0;
    } else if (a == "--prior") {
      tracking.prior = std::atof(v);
    } else if (a == "--temporal") {
      tracking.temporal = std::atof(v);
    } else if (a == "--smoothness") {
      tracking.smoothness = std::atof(v);
    } else if (a == "--spread") {
      tracking.spread = std::atoi(v);
    } else if (a == "--steps") {
      tracking.steps = std::atoi(v);
    } else if (a == "--stereo") {
      tracking.stereo = std::atof(v);
    } else if (a == "--stereo-ncc") {
      tracking.stereo_match.min_ncc = std::atof(v);
    } else if (a == "--stereo-every") {
      tracking.stereo_every = std::atoi(v);
    } else if (a == "--stereo-neighbours") {
      tracking.stereo_match.min_neighbours = std::atoi(v);
    } else if (a == "--stereo-angle") {
      tracking.stereo_match.max_angle = std::atof(v);
    } else {
      std::fprintf(stderr,
                   "usage: %s [--out DIR] [--frames N] [--cameras N] [--width W --height H] "
                   "[--garment M] [--true-silhouettes 0|1] [--reuse 0|1] [--quick 0|1] "
                   "[--true-poses 0|1] [--persons 0|1] [--prior W] [--temporal W] [--smoothness W] "
                   "[--spread N] [--steps N] [--stereo W] [--stereo-neighbours N] "
                   "[--stereo-ncc C] [--stereo-angle RAD] [--stereo-every N]\n",
                   argv[0]);
      return 2;
    }
  }
  if (so.frames < 2 || so.cameras < 3 || so.width < 64 || so.height < 64 || so.garment < 0) {
    std::fprintf(stderr, "garment_bench: 2 frames or more, 3 cameras or more, 64x64 or more\n");
    return 2;
  }
  so.output_dir = out + "/capture";
  std::printf(
      "garment bench: %u cameras at %ux%u (+%u held out), %u frames, shorts' flare %.3f m, "
      "silhouettes %s\n",
      so.cameras, so.width, so.height, so.held_out, so.frames, so.garment,
      so.link_silhouettes ? "true" : "by background subtraction");
  if (persons) std::printf("tracked with the person network's masks and keypoints\n");
  std::fflush(stdout);
  const std::string poses = out + "/poses.json";
  if (!reuse || !std::ifstream(poses)) {
    if (auto r = fvv::RunSynth(so); !r.ok()) return Fail("synth", r.status());
    fvv::TrackCaptureOptions to;
    if (persons) to.persons = fvv::TrackCaptureOptions::Persons::kOn;
    const auto tracked = fvv::TrackCapture(so.output_dir, to);
    if (!tracked.ok()) return Fail("track", tracked.status());
    std::ofstream f(poses);
    f << tracked->ToJson();
    if (!f) return Fail("track", fvv::IoError("cannot write " + poses));
    std::printf("tracked: mean IoU %.3f\n", tracked->mean_iou);
  } else {
    std::printf("the capture and poses of an earlier run in %s\n", out.c_str());
  }
  std::fflush(stdout);

  fvv::EncoderSettings plain;
  // The true poses: what the surface and the fitted body reach where the
  // tracking is not in the way.
  plain.poses = true_poses ? so.output_dir + "/truth/truth.json" : poses;
  if (true_poses) std::printf("encoding with the true poses, not the tracked ones\n");
  plain.refine_shape = true;
  fvv::EncoderSettings surface = plain;
  surface.refine_shape = false;
  surface.surface = true;
  surface.surface_tracking = tracking;
  fvv::EncoderSettings both = plain;
  both.surface = true;
  both.surface_tracking = tracking;
  auto encode = [&](const std::string& name, const fvv::EncoderSettings& s) {
    return fvv::EncodeCapture(so.output_dir, out + "/" + name, s);
  };
  const auto p = encode("plain.fvv", plain);
  if (!p.ok()) return Fail("encode plain", p.status());
  const auto q = encode("surface.fvv", surface);
  if (!q.ok()) return Fail("encode surface", q.status());
  const auto b = quick ? p : encode("both.fvv", both);
  if (!b.ok()) return Fail("encode surface + refine-shape", b.status());
  // The plain stream at the surface stream's total bytes: its PSNR target
  // bisected until the file is within 1 % of it.
  double lo = 20, hi = 60, best_gap = 1e18;
  uint64_t equal_bytes = 0;
  for (int step = 0; step < (quick ? 0 : 10); ++step) {
    fvv::EncoderSettings s = plain;
    s.rate_value = 0.5 * (lo + hi);
    const auto e = encode("plain_equal_try.fvv", s);
    if (!e.ok()) return Fail("encode plain at equal bytes", e.status());
    const double gap = double(e->file_bytes) - double(q->file_bytes);
    if (std::fabs(gap) < best_gap) {
      best_gap = std::fabs(gap);
      equal_bytes = e->file_bytes;
      std::rename((out + "/plain_equal_try.fvv").c_str(), (out + "/plain_equal.fvv").c_str());
    }
    if (std::fabs(gap) < 0.01 * q->file_bytes) break;
    (gap < 0 ? lo : hi) = s.rate_value;
  }

  // Where the garment stands off the plain stream's body.
  const std::string truth = so.output_dir + "/truth";
  const auto base = fvv::DistanceToTrueSurface(out + "/plain.fvv", truth, so.frames);
  if (!base.ok()) return Fail("distances", base.status());
  StandOff off;
  for (const auto& frame : *base) {
    off.emplace_back(frame.size());
    for (size_t v = 0; v < frame.size(); ++v) off.back()[v] = frame[v] > 0.01;
  }
  std::vector<Scored> rows = {{"plain (--refine-shape)", p->file_bytes, 0},
                              {"plain at the surface's bytes", equal_bytes, 0},
                              {"surface (--surface)", q->file_bytes, q->surface_bytes},
                              {"surface + --refine-shape", b->file_bytes, b->surface_bytes}};
  const char* files[] = {"plain.fvv", "plain_equal.fvv", "surface.fvv", "both.fvv"};
  std::printf("%-30s %10s %9s %12s %14s %12s\n", "stream", "bytes", "surface", "whole (mm)",
              "standing (mm)", "held-out dB");
  for (size_t i = 0; i < rows.size(); ++i) {
    if (quick && (i == 1 || i == 3)) continue;
    const std::string stream = out + "/" + files[i];
    const auto dist = i == 0 ? base : fvv::DistanceToTrueSurface(stream, truth, so.frames);
    if (!dist.ok()) return Fail(files[i], dist.status());
    if (auto s = Score(stream, *dist, so, off, &rows[i]); !s.ok()) return Fail(files[i], s);
    std::printf("%-30s %10llu %9llu %12.2f %14.2f %12.2f\n", rows[i].name.c_str(),
                (unsigned long long)rows[i].bytes, (unsigned long long)rows[i].surface_bytes,
                rows[i].whole_mm, rows[i].off_mm, rows[i].psnr);
  }
  std::printf(
      "surface against plain: whole-body distance x%.2f, standing off x%.2f, "
      "held-out %+.2f dB %s\n",
      rows[2].whole_mm / rows[0].whole_mm, rows[2].off_mm / rows[0].off_mm,
      rows[2].psnr - rows[quick ? 0 : 1].psnr, quick ? "at the default rate" : "at equal bytes");
  return 0;
}
