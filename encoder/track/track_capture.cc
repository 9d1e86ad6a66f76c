#include "encoder/track/track_capture.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <nlohmann/json.hpp>

#include "codec/base/thread_pool.h"
#include "encoder/body/body_shape_json.h"
#include "encoder/track/capture_frames.h"
#include "encoder/track/person_observer.h"

namespace fvv {

std::vector<std::vector<double>> TrackCaptureResult::Poses() const {
  std::vector<std::vector<double>> out;
  for (const FrameFit& f : fits) out.push_back(f.dofs);
  return out;
}

std::string TrackCaptureResult::ToJson() const {
  nlohmann::json out;
  out["generator"] = "fvv track";
  out["capture"] = capture.directory;
  nlohmann::json fitted = nlohmann::json::array();
  for (const CaptureCamera& c : capture.cameras) fitted.push_back(c.calibration.name);
  out["cameras"] = fitted;  // those the fit read
  out["silhouettes"] = silhouette_source;
  nlohmann::json names = nlohmann::json::array();
  for (const DofRef& d : model.skeleton.Dofs()) {
    static const char* kKinds[] = {"rx", "ry", "rz", "tx", "ty", "tz"};
    names.push_back(model.skeleton.bones[d.bone].name + "." + kKinds[d.kind]);
  }
  out["dof_names"] = names;
  out["body_shape"] = BodyShapeToJson(shape);
  out["frame_rate"] = capture.frame_rate;
  nlohmann::json list = nlohmann::json::array();
  for (size_t i = 0; i < fits.size(); ++i) {
    const FrameFit& f = fits[i];
    nlohmann::json frame = {{"frame", frames[i]},
                            {"dofs", f.dofs},
                            {"xor_ratio", f.xor_ratio},
                            {"iou", f.iou},
                            {"cameras_used", f.cameras_used},
                            {"flag", f.poor ? f.note : "ok"}};
    if (f.keypoint_distance >= 0) frame["keypoint_distance"] = f.keypoint_distance;
    list.push_back(std::move(frame));
  }
  out["frames"] = list;
  nlohmann::json shifts = nlohmann::json::array();
  for (size_t c = 0; c < camera_shifts.size() && c < capture.cameras.size(); ++c) {
    const CameraShift& s = camera_shifts[c];
    shifts.push_back({{"camera", capture.cameras[c].calibration.name},
                      {"shift_px", {s.shift.pixels.x(), s.shift.pixels.y()}},
                      {"shift_degrees", s.degrees},
                      {"iou", s.shift.iou},
                      {"shifted_iou", s.shift.shifted_iou},
                      {"frames_checked", s.shift.frames},
                      {"calibration_disagrees", s.disagrees}});
  }
  out["camera_shifts"] = shifts;
  out["side_exchanges"] = side_exchanges;
  return out.dump(1) + "\n";
}

bool CalibrationDisagrees(const SilhouetteShift& shift, double degrees) {
  return shift.frames >= 3 && shift.pixels.norm() >= 2 && degrees >= 0.25 &&
         shift.shifted_iou - shift.iou >= 0.01;
}

StatusOr<TrackCaptureResult> TrackCapture(const std::string& path, const TrackCaptureOptions& o) {
  StatusOr<Capture> loaded = LoadCapture(path);
  if (!loaded.ok()) return loaded.status();
  return TrackCapture(*loaded, o);
}

StatusOr<std::unique_ptr<PersonObserver>> PersonsForCapture(const Capture& cap, bool extract,
                                                            TrackCaptureOptions::Persons mode,
                                                            const std::string& models,
                                                            std::string* note) {
  using Persons = TrackCaptureOptions::Persons;
  const bool listed = CaptureReader(cap).HasSilhouettes() && !extract;
  const bool plates = CaptureReader(cap).HasBackgrounds();
  if (mode == Persons::kOff || (mode == Persons::kAuto && (listed || plates))) {
    return std::unique_ptr<PersonObserver>();
  }
  StatusOr<std::unique_ptr<PersonObserver>> observer =
      PersonObserver::Load(models.empty() ? DefaultModelDirectory() : models);
  if (observer.ok() || mode == Persons::kOn) return observer;
  if (note) {
    *note = "no background plates and no person network (" + observer.status().message() +
            "): silhouettes by a temporal median";
  }
  return std::unique_ptr<PersonObserver>();
}

StatusOr<TrackCaptureResult> TrackCapture(const Capture& capture, const TrackCaptureOptions& o) {
  using Clock = std::chrono::steady_clock;
  TrackCaptureResult r;
  r.capture = capture;
  const Capture& cap = r.capture;
  // What is tracked: the frames to fit, which of them start from scratch,
  // and which are reported.
  std::vector<uint32_t> plan;
  std::vector<bool> fresh, reported;
  if (!o.separate_frames.empty()) {
    for (size_t i = 0; i < o.separate_frames.size(); ++i) {
      const uint32_t f = o.separate_frames[i];
      if (f >= cap.frame_count || (i > 0 && f <= o.separate_frames[i - 1])) {
        return InvalidArgument("frame " + std::to_string(f) + " is not within 0.." +
                               std::to_string(cap.frame_count - 1) +
                               " or not after the frame before it");
      }
      plan.push_back(f), fresh.push_back(true), reported.push_back(true);
    }
    r.first = plan.front();
    r.last = plan.back();
  } else {
    r.first = o.first;
    r.last = std::min(o.last, cap.frame_count - 1);
    if (r.first > r.last) {
      return InvalidArgument("frames " + std::to_string(o.first) + ".." + std::to_string(o.last) +
                             " are not within 0.." + std::to_string(cap.frame_count - 1));
    }
    const uint32_t take_last = std::min(o.take_last, cap.frame_count - 1);
    if (r.first < o.take_first || r.last > take_last) {
      return InvalidArgument("frames " + std::to_string(r.first) + ".." + std::to_string(r.last) +
                             " are not within the take's " + std::to_string(o.take_first) + ".." +
                             std::to_string(take_last));
    }
    if (!o.lead_in.empty() && (o.lead_in.size() < 2 || !o.tracker.fixed_shape)) {
      return InvalidArgument("tracking on from earlier poses needs two of them and the shape");
    }
    const uint32_t before = o.lead_in.empty() ? o.warm_up : 0;
    const uint32_t from = r.first - std::min(before, r.first - o.take_first);
    const uint32_t to = r.last + std::min(o.warm_up, take_last - r.last);
    for (uint32_t f = from; f <= to; ++f) {
      plan.push_back(f), fresh.push_back(f == from);
      reported.push_back(f >= r.first && f <= r.last);
    }
  }
  // A missing frame file or a video too short for the plan fails now, not
  // after the frames before.
  FVV_RETURN_IF_ERROR(CheckFramesPresent(cap, plan));
  // Separate frames are not smoothed across each other.
  const PoseSmoothing smoothing = o.separate_frames.empty() ? o.smoothing : PoseSmoothing{0};
  const size_t n = cap.cameras.size();
  ThreadPool pool(std::max(1u, o.tracker.threads));
  std::string note;
  FVV_ASSIGN_OR_RETURN(std::unique_ptr<PersonObserver> persons,
                       PersonsForCapture(cap, o.extract, o.persons, o.person_models, &note));
  if (!note.empty() && o.progress) o.progress("track: " + note);
  StatusOr<std::unique_ptr<CaptureFrames>> frames =
      CaptureFrames::Open(cap, o.extract, &pool, persons.get());
  if (!frames.ok()) return frames.status();
  r.given_silhouettes = (*frames)->given_silhouettes();
  r.silhouette_source = (*frames)->silhouette_source();
  if (o.on_open) o.on_open(**frames);
  std::vector<Camera> cameras;
  for (const CaptureCamera& c : cap.cameras) cameras.push_back(c.calibration);
  StatusOr<std::unique_ptr<Tracker>> tracker = Tracker::Create(cameras, o.tracker);
  if (!tracker.ok()) return tracker.status();

  std::vector<SilhouetteShiftSearch> shifts(n);  // per camera
  CaptureSightings step_sightings;               // the first frames', for the step check
  // Every pair of cameras at every shift: quadratic in cameras, so a rig
  // fitted with more than 16 (--track-cameras all on a dome) is not checked.
  const bool check_steps = persons && o.keypoints && o.separate_frames.empty() && n >= 3 &&
                           n <= 16 && o.step_check_frames >= uint32_t(2 * o.step_check_offset + 2);
  uint32_t reported_count = 0;
  const auto start = Clock::now();
  const bool want_images = o.on_frame || !o.overlays.empty();
  // Frames tracked but not yet reported: their images wait for the frames
  // after them that their smoothed pose reads.
  struct Waiting {
    std::vector<Image> images, silhouettes;
  };
  std::deque<Waiting> waiting;
  std::vector<std::vector<double>> raw;  // the fits' own poses
  std::vector<bool> trusted, angular;
  std::vector<FrameFit> fits;  // every fit, warm-up included
  // The lead-in's poses come first in `raw`: smoothing reads them.
  const size_t lead = o.separate_frames.empty() ? o.lead_in.size() : 0;
  for (size_t i = 0; i < lead; ++i) {
    raw.push_back(o.lead_in[i]);
    trusted.push_back(true);
  }
  for (const DofRef& d : (*tracker)->Model().skeleton.Dofs()) angular.push_back(d.kind < 3);
  auto report = [&](size_t i) -> Status {
    fits[i].dofs = SmoothPose(raw, trusted, angular, lead + i, smoothing);
    Waiting w = std::move(waiting.front());
    waiting.pop_front();
    if (!o.on_frame || !reported[i]) return Status::Ok();
    const auto t3 = Clock::now();
    FVV_RETURN_IF_ERROR(o.on_frame(plan[i], fits[i], **tracker, w.images, w.silhouettes));
    r.callback_seconds += std::chrono::duration<double>(Clock::now() - t3).count();
    return Status::Ok();
  };
  for (size_t step = 0; step < plan.size(); ++step) {
    const uint32_t f = plan[step];
    const auto t0 = Clock::now();
    std::vector<Image> sils, images;
    FVV_RETURN_IF_ERROR((*frames)->Read(f, want_images ? &images : nullptr, &sils));
    // The next frame's images decode while this one is fitted.
    if (step + 1 < plan.size()) (*frames)->Prefetch(plan[step + 1]);
    if (!o.save_silhouettes.empty() && reported[step]) {
      for (uint32_t c = 0; c < n; ++c) {
        char name[64];
        std::snprintf(name, sizeof(name), "_%06u.png", f);
        FVV_RETURN_IF_ERROR(
            WritePng(o.save_silhouettes + "/" + cap.cameras[c].calibration.name + name, sils[c]));
      }
    }
    const auto t1 = Clock::now();
    const std::vector<std::vector<JointSighting>> none;
    const auto& sightings = o.keypoints ? (*frames)->sightings() : none;
    if (check_steps && step_sightings.size() < o.step_check_frames) {
      step_sightings.push_back(sightings);
    }
    if (step == 0 && lead > 0) {
      FVV_RETURN_IF_ERROR((*tracker)->Resume(o.lead_in[lead - 2], o.lead_in[lead - 1], sils));
    }
    StatusOr<FrameFit> fit = fresh[step] && lead == 0 ? (*tracker)->Initialise(sils, sightings)
                                                      : (*tracker)->Track(sils, sightings);
    if (!fit.ok()) {
      return Status(fit.status().code(),
                    "frame " + std::to_string(f) + ": " + fit.status().message());
    }
    const auto t2 = Clock::now();
    r.silhouette_seconds += std::chrono::duration<double>(t1 - t0).count();
    r.fit_seconds += std::chrono::duration<double>(t2 - t1).count();
    if (step == 0) r.first_fit_seconds = r.fit_seconds;
    if (reported[step]) {
      r.flagged += fit->poor;
      r.mean_iou += fit->iou;
      if (reported_count++ % std::max(1u, o.shift_check_every) == 0) {
        pool.Run(uint32_t(n), [&](uint32_t c) {
          shifts[c].Add((*tracker)->ModelSilhouette(c, fit->dofs), sils[c]);
        });
      }
    } else {
      ++r.warm_up_frames;
    }
    if (!o.overlays.empty() && reported[step]) {
      // The camera images with the fit drawn over them: model only in red,
      // silhouette only in blue, agreement unchanged.
      std::vector<Image> tiles;
      for (uint32_t c = 0; c < n; ++c) {
        Image image = images[c];
        const Image model = (*tracker)->ModelSilhouette(c, fit->dofs);
        for (size_t i = 0; i < model.pixels.size(); ++i) {
          const bool m = model.pixels[i] != 0, s = sils[c].pixels[i] != 0;
          if (m == s) continue;
          uint8_t* p = &image.pixels[3 * i];
          p[0] = m ? 255 : 0, p[1] = 0, p[2] = m ? 0 : 255;
        }
        tiles.push_back(std::move(image));
      }
      char name[64];
      std::snprintf(name, sizeof(name), "/overlay_%06u.png", f);
      FVV_RETURN_IF_ERROR(WritePng(o.overlays + name, MakeContactSheet(tiles)));
    }
    if (o.progress) {
      const double elapsed = std::chrono::duration<double>(Clock::now() - start).count();
      const size_t done = step + 1, total = plan.size();
      char keypoints[48] = "";
      if (fit->keypoint_distance >= 0) {
        std::snprintf(keypoints, sizeof(keypoints), "  keypoints %.1f%% off",
                      100 * fit->keypoint_distance);
      }
      char line[320];
      std::snprintf(line, sizeof(line),
                    "track: frame %u (%zu/%zu)%s  IoU %.3f  XOR %.1f%%%s  %d evaluations  %s  "
                    "%.2f s/frame, ETA %.0f s",
                    f, done, total, reported[step] ? "" : " warm-up", fit->iou,
                    100 * fit->xor_ratio, keypoints, fit->evaluations,
                    fit->poor ? fit->note.c_str() : "ok", elapsed / done,
                    elapsed / done * (total - done));
      o.progress(line);
    }
    raw.push_back(fit->dofs);
    trusted.push_back(!fit->poor);
    fits.push_back(std::move(*fit));
    waiting.push_back({std::move(images), std::move(sils)});
    const size_t next = fits.size() - waiting.size();
    if (fits.size() > next + size_t(smoothing.Radius())) FVV_RETURN_IF_ERROR(report(next));
  }
  while (!waiting.empty()) FVV_RETURN_IF_ERROR(report(fits.size() - waiting.size()));
  for (size_t i = 0; i < plan.size(); ++i) {
    if (reported[i]) {
      r.frames.push_back(plan[i]);
      r.fits.push_back(std::move(fits[i]));
    } else if (plan[i] > r.last) {
      r.after_frames.push_back(plan[i]);
      r.after_poses.push_back(fits[i].dofs);
    }
  }
  r.mean_iou /= r.fits.size();
  for (size_t c = 0; c < n; ++c) {
    TrackCaptureResult::CameraShift cs;
    cs.shift = shifts[c].Best();
    const double focal = cameras[c].fx;
    cs.degrees = focal > 0 ? std::atan(cs.shift.pixels.norm() / focal) * 180 / M_PI : 0;
    cs.disagrees = CalibrationDisagrees(cs.shift, cs.degrees);
    r.camera_shifts.push_back(cs);
  }
  if (check_steps && step_sightings.size() >= size_t(2 * o.step_check_offset + 2)) {
    FrameOffsetOptions so;
    so.max_offset = o.step_check_offset;
    StatusOr<FrameOffsets> steps = EstimateFrameOffsets(cameras, step_sightings, so);
    if (steps.ok()) {
      r.steps = std::move(*steps);
      r.out_of_step = CamerasOutOfStep(r.steps);
    }
  }
  r.decode_seconds = (*frames)->decode_seconds();
  r.person_seconds = (*frames)->person_seconds();
  r.side_exchanges = (*frames)->side_exchanges();
  r.shape = (*tracker)->shape();
  r.model = (*tracker)->Model();
  return r;
}

}  // namespace fvv
