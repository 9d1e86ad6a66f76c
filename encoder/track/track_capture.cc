#include "encoder/track/track_capture.h"

#include <chrono>
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
  out["silhouettes"] = silhouette_source;
  nlohmann::json names = nlohmann::json::array();
  for (const DofRef& d : model.skeleton.Dofs()) {
    static const char* kKinds[] = {"rx", "ry", "rz", "tx", "ty", "tz"};
    names.push_back(model.skeleton.bones[d.bone].name + "." + kKinds[d.kind]);
  }
  out["dof_names"] = names;
  out["body_shape"] = BodyShapeToJson(shape);
  out["frame_rate"] = capture.frame_rate;
  nlohmann::json frames = nlohmann::json::array();
  for (size_t i = 0; i < fits.size(); ++i) {
    const FrameFit& f = fits[i];
    nlohmann::json frame = {{"frame", first + i},
                            {"dofs", f.dofs},
                            {"xor_ratio", f.xor_ratio},
                            {"iou", f.iou},
                            {"cameras_used", f.cameras_used},
                            {"flag", f.poor ? f.note : "ok"}};
    if (f.keypoint_distance >= 0) frame["keypoint_distance"] = f.keypoint_distance;
    frames.push_back(std::move(frame));
  }
  out["frames"] = frames;
  return out.dump(1) + "\n";
}

StatusOr<TrackCaptureResult> TrackCapture(const std::string& path, const TrackCaptureOptions& o) {
  using Clock = std::chrono::steady_clock;
  StatusOr<Capture> loaded = LoadCapture(path);
  if (!loaded.ok()) return loaded.status();
  TrackCaptureResult r;
  r.capture = *loaded;
  const Capture& cap = r.capture;
  r.first = o.first;
  r.last = std::min(o.last, cap.frame_count - 1);
  if (r.first > r.last) {
    return InvalidArgument("frames " + std::to_string(o.first) + ".." + std::to_string(o.last) +
                           " are not within 0.." + std::to_string(cap.frame_count - 1));
  }
  const size_t n = cap.cameras.size();
  ThreadPool pool(2);
  std::unique_ptr<PersonObserver> persons;
  const bool listed = CaptureReader(cap).HasSilhouettes() && !o.extract;
  const bool plates = CaptureReader(cap).HasBackgrounds();
  if (o.persons == TrackCaptureOptions::Persons::kOn ||
      (o.persons == TrackCaptureOptions::Persons::kAuto && !listed && !plates)) {
    StatusOr<std::unique_ptr<PersonObserver>> observer =
        PersonObserver::Load(o.person_models.empty() ? DefaultModelDirectory() : o.person_models);
    if (observer.ok()) {
      persons = std::move(*observer);
    } else if (o.persons == TrackCaptureOptions::Persons::kOn) {
      return observer.status();
    } else if (o.progress) {
      o.progress("track: no background plates and no person network (" +
                 observer.status().message() + "): silhouettes by a temporal median");
    }
  }
  StatusOr<std::unique_ptr<CaptureFrames>> frames =
      CaptureFrames::Open(cap, o.extract, &pool, persons.get());
  if (!frames.ok()) return frames.status();
  r.given_silhouettes = (*frames)->given_silhouettes();
  r.silhouette_source = (*frames)->silhouette_source();
  std::vector<Camera> cameras;
  for (const CaptureCamera& c : cap.cameras) cameras.push_back(c.calibration);
  StatusOr<std::unique_ptr<Tracker>> tracker = Tracker::Create(cameras, o.tracker);
  if (!tracker.ok()) return tracker.status();

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
  auto report = [&](size_t i) -> Status {
    r.fits[i].dofs = SmoothPose(raw, trusted, angular, i, o.smoothing);
    Waiting w = std::move(waiting.front());
    waiting.pop_front();
    if (!o.on_frame) return Status::Ok();
    const auto t3 = Clock::now();
    FVV_RETURN_IF_ERROR(
        o.on_frame(r.first + uint32_t(i), r.fits[i], **tracker, w.images, w.silhouettes));
    r.callback_seconds += std::chrono::duration<double>(Clock::now() - t3).count();
    return Status::Ok();
  };
  for (uint32_t f = r.first; f <= r.last; ++f) {
    const auto t0 = Clock::now();
    std::vector<Image> sils, images;
    FVV_RETURN_IF_ERROR((*frames)->Read(f, want_images ? &images : nullptr, &sils));
    if (!o.save_silhouettes.empty()) {
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
    StatusOr<FrameFit> fit =
        f == r.first ? (*tracker)->Initialise(sils, sightings) : (*tracker)->Track(sils, sightings);
    if (!fit.ok()) {
      return Status(fit.status().code(),
                    "frame " + std::to_string(f) + ": " + fit.status().message());
    }
    const auto t2 = Clock::now();
    r.silhouette_seconds += std::chrono::duration<double>(t1 - t0).count();
    r.fit_seconds += std::chrono::duration<double>(t2 - t1).count();
    if (f == r.first) r.first_fit_seconds = r.fit_seconds;
    r.flagged += fit->poor;
    r.mean_iou += fit->iou;
    if (!o.overlays.empty()) {
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
      const uint32_t done = f - r.first + 1, total = r.last - r.first + 1;
      char keypoints[48] = "";
      if (fit->keypoint_distance >= 0) {
        std::snprintf(keypoints, sizeof(keypoints), "  keypoints %.1f%% off",
                      100 * fit->keypoint_distance);
      }
      char line[320];
      std::snprintf(line, sizeof(line),
                    "track: frame %u (%u/%u)  IoU %.3f  XOR %.1f%%%s  %d evaluations  %s  %.2f "
                    "s/frame, ETA %.0f s",
                    f, done, total, fit->iou, 100 * fit->xor_ratio, keypoints, fit->evaluations,
                    fit->poor ? fit->note.c_str() : "ok", elapsed / done,
                    elapsed / done * (total - done));
      o.progress(line);
    }
    if (angular.empty()) {
      for (const DofRef& d : (*tracker)->Model().skeleton.Dofs()) angular.push_back(d.kind < 3);
    }
    raw.push_back(fit->dofs);
    trusted.push_back(!fit->poor);
    r.fits.push_back(std::move(*fit));
    waiting.push_back({std::move(images), std::move(sils)});
    const size_t reported = r.fits.size() - waiting.size();
    if (r.fits.size() > reported + size_t(o.smoothing.Radius())) {
      FVV_RETURN_IF_ERROR(report(reported));
    }
  }
  while (!waiting.empty()) FVV_RETURN_IF_ERROR(report(r.fits.size() - waiting.size()));
  r.mean_iou /= r.fits.size();
  r.decode_seconds = (*frames)->decode_seconds();
  r.person_seconds = (*frames)->person_seconds();
  r.shape = (*tracker)->shape();
  r.model = (*tracker)->Model();
  return r;
}

}  // namespace fvv
