#include "encoder/cli/track_command.h"

#include <chrono>
#include <cstdio>
#include <fstream>
#include <memory>

#include <nlohmann/json.hpp>

#include "codec/thread_pool.h"
#include "encoder/body/kinematics.h"
#include "encoder/capture/capture.h"
#include "encoder/capture/joint_truth.h"
#include "encoder/capture/silhouette.h"
#include "encoder/capture/tracker.h"

namespace fvv {
namespace {

struct TrackArgs {
  std::string capture, output, truth, save_silhouettes, overlays;
  std::string frames;  // "A:B"
  bool extract = false;
  bool no_shape = false;
  bool quiet = false;
};

int Fail(const Status& s) {
  std::fprintf(stderr, "fvv: %s\n", s.ToString().c_str());
  return 1;
}

int RunTrack(const TrackArgs& a) {
  using Clock = std::chrono::steady_clock;
  StatusOr<Capture> loaded = LoadCapture(a.capture);
  if (!loaded.ok()) return Fail(loaded.status());
  const Capture& cap = *loaded;
  CaptureReader reader(cap);
  uint32_t first = 0, last = cap.frame_count - 1;
  if (!a.frames.empty()) {
    unsigned f0 = 0, f1 = 0;
    char tail = 0;
    if (std::sscanf(a.frames.c_str(), "%u:%u%c", &f0, &f1, &tail) != 2 || f0 > f1 || f1 >= cap.frame_count) {
      return Fail(InvalidArgument("--frames " + a.frames + " is not a range A:B within 0.." +
                                  std::to_string(cap.frame_count - 1)));
    }
    first = f0, last = f1;
  }
  const size_t n_cams = cap.cameras.size();
  const bool given = reader.HasSilhouettes() && !a.extract;
  std::vector<BackgroundModel> backgrounds(n_cams);
  if (!given) {
    for (uint32_t c = 0; c < n_cams; ++c) {
      if (cap.cameras[c].background) {
        StatusOr<Image> plate = reader.ReadBackground(c);
        if (!plate.ok()) return Fail(plate.status());
        backgrounds[c].colour = std::move(*plate);
      } else {
        // No plate: the temporal median of up to 15 frames spread over the take.
        std::vector<Image> samples;
        const uint32_t count = std::min<uint32_t>(15, cap.frame_count);
        for (uint32_t k = 0; k < count; ++k) {
          StatusOr<Image> f = reader.ReadFrame(c, uint32_t(uint64_t(k) * (cap.frame_count - 1) / std::max(1u, count - 1)));
          if (!f.ok()) return Fail(f.status());
          samples.push_back(std::move(*f));
        }
        backgrounds[c].colour = TemporalMedian(samples);
      }
    }
  }
  std::vector<Camera> cameras;
  for (const CaptureCamera& c : cap.cameras) cameras.push_back(c.calibration);
  TrackerOptions options;
  options.adapt_shape = !a.no_shape;
  StatusOr<std::unique_ptr<Tracker>> tracker = Tracker::Create(cameras, options);
  if (!tracker.ok()) return Fail(tracker.status());

  ThreadPool pool(2);
  nlohmann::json frames = nlohmann::json::array();
  std::vector<std::vector<double>> poses;
  const auto start = Clock::now();
  double silhouette_s = 0, fit_s = 0;
  int flagged = 0;
  for (uint32_t f = first; f <= last; ++f) {
    auto t0 = Clock::now();
    std::vector<Image> sils(n_cams);
    std::vector<Status> errors(n_cams);
    pool.Run(uint32_t(n_cams), [&](uint32_t c) {
      StatusOr<Image> s = given ? reader.ReadSilhouette(c, f) : reader.ReadFrame(c, f);
      if (s.ok() && !given) s = ExtractSilhouette(*s, backgrounds[c]);
      if (!s.ok()) {
        errors[c] = s.status();
        return;
      }
      sils[c] = std::move(*s);
    });
    for (const Status& s : errors) {
      if (!s.ok()) return Fail(s);
    }
    if (!a.save_silhouettes.empty()) {
      for (uint32_t c = 0; c < n_cams; ++c) {
        char name[512];
        std::snprintf(name, sizeof(name), "%s/%s_%06u.png", a.save_silhouettes.c_str(),
                      cap.cameras[c].calibration.name.c_str(), f);
        Status s = WritePng(name, sils[c]);
        if (!s.ok()) return Fail(s);
      }
    }
    auto t1 = Clock::now();
    StatusOr<FrameFit> fit = f == first ? (*tracker)->Initialise(sils) : (*tracker)->Track(sils);
    if (!fit.ok()) {
      return Fail(Status(fit.status().code(), "frame " + std::to_string(f) + ": " + fit.status().message()));
    }
    auto t2 = Clock::now();
    silhouette_s += std::chrono::duration<double>(t1 - t0).count();
    fit_s += std::chrono::duration<double>(t2 - t1).count();
    flagged += fit->poor;
    if (!a.overlays.empty()) {
      // The camera images with the fit drawn over them: model only in red,
      // silhouette only in blue, both unchanged.
      std::vector<Image> tiles;
      for (uint32_t c = 0; c < n_cams; ++c) {
        StatusOr<Image> image = reader.ReadFrame(c, f);
        if (!image.ok()) return Fail(image.status());
        const Image model = (*tracker)->ModelSilhouette(c, fit->dofs);
        for (size_t i = 0; i < model.pixels.size(); ++i) {
          const bool m = model.pixels[i] != 0, s = sils[c].pixels[i] != 0;
          if (m == s) continue;
          uint8_t* p = &image->pixels[3 * i];
          p[0] = m ? 255 : 0, p[1] = 0, p[2] = m ? 0 : 255;
        }
        tiles.push_back(std::move(*image));
      }
      char name[512];
      std::snprintf(name, sizeof(name), "%s/overlay_%06u.png", a.overlays.c_str(), f);
      Status s = WritePng(name, MakeContactSheet(tiles));
      if (!s.ok()) return Fail(s);
    }
    poses.push_back(fit->dofs);
    nlohmann::json jf;
    jf["frame"] = f;
    jf["dofs"] = fit->dofs;
    jf["xor_ratio"] = fit->xor_ratio;
    jf["iou"] = fit->iou;
    jf["cameras_used"] = fit->cameras_used;
    jf["flag"] = fit->poor ? fit->note : "ok";
    frames.push_back(jf);
    if (!a.quiet) {
      const double elapsed = std::chrono::duration<double>(Clock::now() - start).count();
      const uint32_t done = f - first + 1, total = last - first + 1;
      std::fprintf(stderr, "track: frame %u (%u/%u)  IoU %.3f  XOR %.1f%%  %d evaluations  %s  %.2f s/frame, ETA %.0f s\n", f,
                   done, total, fit->iou, 100 * fit->xor_ratio, fit->evaluations, fit->poor ? fit->note.c_str() : "ok",
                   elapsed / done, elapsed / done * (total - done));
    }
  }
  const BodyModel model = (*tracker)->Model();
  const BodyShape& shape = (*tracker)->shape();
  nlohmann::json out;
  out["generator"] = "fvv track";
  out["capture"] = a.capture;
  out["silhouettes"] = given ? "given" : "background subtraction";
  nlohmann::json names = nlohmann::json::array();
  for (const DofRef& d : model.skeleton.Dofs()) {
    static const char* kKinds[] = {"rx", "ry", "rz", "tx", "ty", "tz"};
    names.push_back(model.skeleton.bones[d.bone].name + "." + kKinds[d.kind]);
  }
  out["dof_names"] = names;
  out["body_shape"] = {{"stature", shape.stature},
                       {"length", shape.length},
                       {"girth", shape.girth}};
  out["frame_rate"] = cap.frame_rate;
  out["frames"] = frames;
  const std::string text = out.dump(1) + "\n";
  Status s = WriteFileAtomic(a.output, reinterpret_cast<const uint8_t*>(text.data()), text.size());
  if (!s.ok()) return Fail(s);
  const uint32_t count = last - first + 1;
  double mean_iou = 0;
  for (const auto& jf : frames) mean_iou += jf["iou"].get<double>();
  mean_iou /= count;
  std::printf("tracked frames %u..%u of %s: %u frames, %d flagged\n", first, last, a.capture.c_str(), count,
              flagged);
  std::printf("  body shape: stature %.3f (%.2f m), girth %.3f, arm length %.3f, leg length %.3f\n",
              shape.stature, 1.75 * shape.stature, shape.girth[kSegChest], shape.length[kSegLeftUpperArm],
              shape.length[kSegLeftThigh]);
  std::printf("  silhouettes: %s, mean IoU %.3f\n", given ? "given" : "background subtraction", mean_iou);
  std::printf("  time: %.3f s per frame (silhouettes %.3f, fitting %.3f)\n", (silhouette_s + fit_s) / count,
              silhouette_s / count, fit_s / count);
  if (!a.truth.empty()) {
    StatusOr<JointErrors> e = CompareWithTruth(a.truth, model.skeleton, poses, first);
    if (!e.ok()) return Fail(e.status());
    std::printf("  joint error against %s: mean %.2f cm, max %.2f cm (%zu joints: %s)\n", a.truth.c_str(),
                100 * e->mean, 100 * e->max, e->joints.size(), e->Describe().c_str());
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
  t->add_option("--truth", a->truth, "Ground truth (fvv synth's truth.json or its directory): joint errors");
  t->add_option("--frames", a->frames, "Frame range A:B (default all)");
  t->add_flag("--extract", a->extract,
              "Background subtraction even when the capture lists silhouettes");
  t->add_flag("--fixed-shape", a->no_shape, "Keep the generic body's proportions");
  t->add_option("--save-silhouettes", a->save_silhouettes, "Write the silhouettes used (PNG) here")
      ->check(CLI::ExistingDirectory);
  t->add_option("--overlays", a->overlays,
                "Write each frame's cameras with the fit drawn over them (PNG) here")
      ->check(CLI::ExistingDirectory);
  t->add_flag("-q,--quiet", a->quiet, "No per-frame progress");
  t->callback([a, exit_code] { *exit_code = RunTrack(*a); });
}

}  // namespace fvv
