#include "tools/fvv/track_command.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <memory>

#include "encoder/capture/up_axis.h"
#include "encoder/encode/prepared_take.h"
#include "encoder/io/image_io.h"
#include "encoder/track/camera_choice.h"
#include "encoder/track/joint_truth.h"
#include "encoder/track/silhouette_truth.h"
#include "encoder/track/track_capture.h"
#include "tools/fvv/frame_range.h"
#include "tools/fvv/persons_option.h"
#include "tools/fvv/shard_option.h"
#include "tools/fvv/smooth_option.h"

namespace fvv {
namespace {

struct TrackArgs {
  std::string capture, output, truth, save_silhouettes, overlays;
  std::string frames;  // "A:B"
  std::string prepared, shard, after;
  bool extract = false;
  std::string persons = "auto", models;
  std::string track_cameras = "auto";  // a count, "all", or "auto"
  bool no_shape = false;
  bool no_keypoints = false;
  bool quiet = false;
  unsigned threads = 2;
  double smooth = TrackCaptureOptions{}.smoothing.sigma_frames;
};

int Fail(const Status& s) {
  std::fprintf(stderr, "fvv: %s\n", s.ToString().c_str());
  return 1;
}

int RunTrack(const TrackArgs& a) {
  TrackCaptureOptions o;
  const Status range = ParseFrameRange(a.frames, &o.first, &o.last);
  if (!range.ok()) return Fail(range);
  o.smoothing.sigma_frames = a.smooth;  // before GoOnAfter, which keeps what it reads
  uint32_t shard_k = 0, shard_n = 0;    // --shard K/N
  if (!a.shard.empty()) {
    const Status parsed = ParseShard(a.shard, &shard_k, &shard_n);
    if (!parsed.ok()) return Fail(parsed);
  }
  if (!a.prepared.empty()) {
    // The frames a shard (or a whole-take encode) of a prepared take tracks,
    // with its shape and warm-up.
    if (!a.frames.empty()) {
      return Fail(InvalidArgument("--frames with --prepared: the prepared take sets the frames"));
    }
    StatusOr<PreparedTake> take = LoadPreparedTakeDescription(a.prepared);
    if (!take.ok()) return Fail(take.status());
    if (!take->shards_track) {
      return Fail(InvalidArgument(a.prepared +
                                  " was prepared with poses: its shards use them, they do not "
                                  "track (fvv encode --prepare without --poses)"));
    }
    uint32_t first = take->first_frame, last = take->last_frame;
    if (!a.shard.empty()) {
      StatusOr<ShardFrames> part =
          ShardFramesOf(take->frames(), take->gop_frames, shard_k, shard_n);
      if (!part.ok()) return Fail(part.status());
      first = take->first_frame + part->first;
      last = first + part->count - 1;
    }
    UsePreparedTracking(*take, first, last, &o);
    if (!a.after.empty()) {
      if (a.shard.empty() || shard_k == 0) {
        return Fail(InvalidArgument("--after goes with --shard K/N, K above 0"));
      }
      const Status after = GoOnAfter(a.after, shard_k, shard_n, &o);
      if (!after.ok()) return Fail(after);
    }
  } else if (!a.shard.empty() || !a.after.empty()) {
    return Fail(
        InvalidArgument("--shard needs --prepared DIR (fvv encode --prepare DIR writes it)"));
  }
  o.extract = a.extract;
  o.tracker.threads = a.threads;
  o.persons = PersonsSetting(a.persons);
  o.person_models = a.models;
  o.keypoints = !a.no_keypoints;
  if (a.no_shape && !o.tracker.fixed_shape) o.tracker.adapt_shape = false;
  o.save_silhouettes = a.save_silhouettes;
  o.overlays = a.overlays;
  for (const std::string& dir : {a.save_silhouettes, a.overlays}) {
    if (dir.empty()) continue;
    const Status made = MakeDirectories(dir);
    if (!made.ok()) return Fail(made);
  }
  if (!a.quiet)
    o.progress = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };
  StatusOr<Capture> capture = LoadCapture(a.capture);
  if (!capture.ok()) return Fail(capture.status());
  // A world whose up the cameras contradict: said before the long work.
  const std::string upright = UprightWarning(capture->cameras, capture->declared_up_axis);
  if (!upright.empty()) std::fprintf(stderr, "warning: %s\n", upright.c_str());
  // Of a studio's many cameras, the fit reads a spread few.
  StatusOr<uint32_t> setting = ParseTrackingCameras(a.track_cameras);
  if (!setting.ok()) return Fail(setting.status());
  std::string names;
  const Capture fit =
      FittingCapture(*capture, TrackingCameraCount(*setting, capture->cameras.size()), &names);
  if (fit.cameras.size() < capture->cameras.size()) {
    std::fprintf(stderr, "track: fitting with %zu of %zu cameras (--track-cameras): %s\n",
                 fit.cameras.size(), capture->cameras.size(), names.c_str());
  }
  StatusOr<TrackCaptureResult> r = TrackCapture(fit, o);
  if (!r.ok()) return Fail(r.status());
  const std::string text = r->ToJson();
  Status s = WriteFileAtomic(a.output, reinterpret_cast<const uint8_t*>(text.data()), text.size());
  if (!s.ok()) return Fail(s);
  const size_t count = r->fits.size();
  std::printf("tracked frames %u..%u of %s: %zu frames, %d flagged\n", r->first, r->last,
              a.capture.c_str(), count, r->flagged);
  if (r->warm_up_frames > 0) {
    std::printf("  warm-up: %u frames tracked around them, not reported\n", r->warm_up_frames);
  }
  {
    // Height standing, and each proportion against the generic body's.
    double bottom = 1e30, top = -1e30;
    for (const auto& v : r->model.mesh.positions) {
      bottom = std::min(bottom, double(v[1]));
      top = std::max(top, double(v[1]));
    }
    const BodyShape& b = r->shape;
    std::printf(
        "  body shape: %.2f m tall (stature %.3f); length / girth: head %.2f / %.2f, trunk %.2f / "
        "%.2f, arms %.2f / %.2f, legs %.2f / %.2f, neck girth %.2f of the "
        "head's\n",
        top - bottom, b.stature, b.length[kSegHead], b.girth[kSegHead], b.length[kSegChest],
        b.girth[kSegChest], b.length[kSegLeftUpperArm], b.girth[kSegLeftUpperArm],
        b.length[kSegLeftThigh], b.girth[kSegLeftThigh], b.neck_ratio);
  }
  std::printf("  silhouettes: %s, mean IoU %.3f\n", r->silhouette_source.c_str(), r->mean_iou);
  if (r->side_exchanges > 0) {
    std::printf(
        "  keypoints: left and right exchanged in %u camera frames, where one camera named them "
        "the other way round from the others\n",
        r->side_exchanges);
  }
  // A camera that sees the fit beside the actor by the same pixels in every
  // frame: its calibration, not the tracking.
  for (size_t c = 0; c < r->camera_shifts.size(); ++c) {
    const TrackCaptureResult::CameraShift& cs = r->camera_shifts[c];
    if (!cs.disagrees) continue;
    std::printf(
        "  warning: %s sees the fit %+.0f, %+.0f px off its silhouettes in every frame checked "
        "(%d; a turn of %.2f degrees; IoU %.3f, %.3f with that shift): its calibration "
        "disagrees with the other cameras' (fvv capture refine-calib; docs/tracking.md)\n",
        r->capture.cameras[c].calibration.name.c_str(), -cs.shift.pixels.x(), -cs.shift.pixels.y(),
        cs.shift.frames, cs.degrees, cs.shift.iou, cs.shift.shifted_iou);
  }
  // Cameras whose keypoints meet clearly better a frame or more apart.
  if (r->out_of_step) {
    std::string which;
    for (size_t c = 0; c < r->steps.offsets.size(); ++c) {
      char part[160];
      std::snprintf(part, sizeof(part), "%s%s %+d (keypoints %.1f -> %.1f px)",
                    which.empty() ? "" : ", ", r->capture.cameras[c].calibration.name.c_str(),
                    r->steps.offsets[c], r->steps.before_px[c], r->steps.after_px[c]);
      which += part;
    }
    std::printf(
        "  warning: the cameras look out of step (the first frames tracked, %u compared): their "
        "keypoints meet best with these frame offsets: %s; check with the masks' tangents, "
        "which place no joint (fvv capture sync --from tangents), bring them in step with fvv "
        "capture sync --write and track again\n",
        r->steps.frames, which.c_str());
  }
  // Per frame tracked, warm-up included.
  const size_t tracked = count + r->warm_up_frames;
  std::printf("  time: %.3f s per frame (silhouettes %.3f, fitting %.3f)\n",
              (r->silhouette_seconds + r->fit_seconds) / tracked, r->silhouette_seconds / tracked,
              r->fit_seconds / tracked);
  if (r->person_seconds > 0) {
    std::printf(
        "        of the silhouettes: decoding %.3f, person network %.3f s per frame (%zu "
        "cameras)\n",
        r->decode_seconds / tracked, r->person_seconds / tracked, r->capture.cameras.size());
  }
  if (tracked > 1) {
    // The first frame (initialisation) is a one-off: what a longer take costs per frame.
    const double later = (r->silhouette_seconds + r->fit_seconds - r->first_fit_seconds -
                          r->silhouette_seconds / tracked) /
                         (tracked - 1);
    std::printf("        the first frame's fit %.1f s, every later frame %.3f s\n",
                r->first_fit_seconds, later);
  }
  if (!a.truth.empty()) {
    StatusOr<JointErrors> e = CompareWithTruth(a.truth, r->model.skeleton, r->Poses(), r->first);
    if (!e.ok()) return Fail(e.status());
    std::printf("  joint error against %s: mean %.2f cm, max %.2f cm (%zu joints: %s)\n",
                a.truth.c_str(), 100 * e->mean, 100 * e->max, e->joints.size(),
                e->Describe().c_str());
    // Where the error is: drift while tracking shows as a rising run of frames.
    const std::vector<double>& f = e->per_frame;
    const size_t worst = size_t(std::max_element(f.begin(), f.end()) - f.begin());
    const size_t best = size_t(std::min_element(f.begin(), f.end()) - f.begin());
    std::printf("  per frame: best frame %u (%.2f cm), worst frame %u (%.2f cm)\n",
                r->first + unsigned(best), 100 * f[best], r->first + unsigned(worst),
                100 * f[worst]);
    if (f.size() <= 100) {
      for (size_t i = 0; i < f.size(); ++i)
        std::printf("%s%5.1f%s", i % 10 == 0 ? "    cm:" : "", 100 * f[i],
                    i % 10 == 9 || i + 1 == f.size() ? "\n" : "");
    }
    // Per joint: a large mean offset is a bias (joint placement inside the
    // body, a proportion), the rest moves from frame to frame.
    std::printf("  per joint (mean error, mean offset x y z in cm):\n");
    for (size_t k = 0; k < e->joints.size(); ++k) {
      const Eigen::Vector3d& off = e->per_joint_offset[k];
      std::printf("    %-11s %5.1f  (%+5.1f %+5.1f %+5.1f)\n", e->joints[k].c_str(),
                  100 * e->per_joint_mean[k], 100 * off.x(), 100 * off.y(), 100 * off.z());
    }
    // What the masks themselves allow: the silhouettes read against the true ones.
    if (!a.save_silhouettes.empty()) {
      std::vector<std::string> cams;
      for (const auto& c : r->capture.cameras) cams.push_back(c.calibration.name);
      StatusOr<SilhouetteAgreement> sa =
          CompareSilhouettesWithTruth(a.truth, a.save_silhouettes, cams, r->first, r->last);
      if (!sa.ok()) return Fail(sa.status());
      std::printf("  silhouettes against the true ones: mean IoU %.3f over %u frames (", sa->mean,
                  sa->frames);
      for (size_t c = 0; c < cams.size(); ++c) {
        std::printf("%s%s %.3f", c ? ", " : "", cams[c].c_str(), sa->iou[c]);
      }
      std::printf(")\n");
    }
  }
  std::printf("  poses: %s\n", a.output.c_str());
  return 0;
}

}  // namespace

void AddTrackCommand(CLI::App* app, int* exit_code) {
  auto a = std::make_shared<TrackArgs>();
  CLI::App* t = app->add_subcommand(
      "track", "Marker-free motion capture: fit the body model to a capture's silhouettes");
  t->add_option("capture", a->capture, "Capture directory or capture.json")->required();
  t->add_option("-o,--output", a->output, "Poses (JSON): DOFs, fit quality and flags per frame")
      ->required();
  t->add_option("--truth", a->truth,
                "Ground truth (fvv synth's truth.json or its directory): joint errors, and with "
                "--save-silhouettes the silhouettes' IoU against the true ones");
  t->add_option("--frames", a->frames, "Frame range A:B (default all)");
  t->add_option("--prepared", a->prepared,
                "Track as the shards of this prepared take do (fvv encode --prepare without "
                "--poses): its frames, its shape fixed, its warm-up frames around them");
  t->add_option("--shard", a->shard, "With --prepared: only the frames of shard K of N");
  t->add_option("--after", a->after,
                "With --shard K/N: go on from the poses of this part (K-1), as fvv encode "
                "--after does")
      ->check(CLI::ExistingFile);
  t->add_flag("--extract", a->extract,
              "Background subtraction even when the capture lists silhouettes");
  AddPersonsOptions(t, "to fit", &a->persons, &a->models);
  t->add_flag("--no-keypoints", a->no_keypoints,
              "With person masks, fit silhouettes only (the network's body keypoints neither "
              "place the body nor hold the fit)");
  t->add_flag("--fixed-shape", a->no_shape, "Keep the generic body's proportions");
  t->add_option("--track-cameras", a->track_cameras,
                "Cameras the fit reads: a count (chosen to see the actor whole and stand as far "
                "apart as they go), all, or auto (" +
                    std::to_string(kDefaultTrackingCameras) + " of a rig of over " +
                    std::to_string(kAutoTrackingAbove) +
                    ", else all). The poses hold for every camera's texture")
      ->capture_default_str();
  AddSmoothOption(t, &a->smooth);
  t->add_option("--save-silhouettes", a->save_silhouettes,
                "Write the silhouettes used (PNG) here (created if missing)");
  t->add_option("--overlays", a->overlays,
                "Write each frame's cameras with the fit drawn over them (PNG) here (created if "
                "missing)");
  t->add_option("--threads", a->threads, "Worker threads")
      ->check(CLI::Range(1u, 256u))
      ->capture_default_str();
  t->add_flag("-q,--quiet", a->quiet, "No per-frame progress");
  t->callback([a, exit_code] { *exit_code = RunTrack(*a); });
}

}  // namespace fvv
