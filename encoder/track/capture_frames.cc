#include "encoder/track/capture_frames.h"

#include <chrono>
#include <cmath>
#include <future>
#include <optional>

#include "encoder/track/person_selection.h"
#include "encoder/track/sighting_sides.h"

namespace fvv {
namespace {

// How far a person's hips may be from where another camera's view puts them,
// as a share of the person's region (about 1.25 times its height).
constexpr double kHipTolerance = 0.15;

}  // namespace

StatusOr<std::unique_ptr<CaptureFrames>> CaptureFrames::Open(const Capture& capture, bool extract,
                                                             ThreadPool* pool,
                                                             PersonObserver* persons) {
  std::unique_ptr<CaptureFrames> f(new CaptureFrames(capture, pool));
  CaptureReader& reader = f->reader_;
  const size_t n = capture.cameras.size();
  f->given_ = reader.HasSilhouettes() && !extract;
  if (f->given_) return f;
  f->plates_ = reader.HasBackgrounds();
  if (persons) {
    f->persons_ = persons;
    f->regions_.assign(n, PersonRegion());
    for (const CaptureCamera& c : capture.cameras) f->cameras_.push_back(c.calibration);
    // Without plates the network's masks are the silhouettes: no median needed.
    if (!f->plates_) return f;
  }
  f->backgrounds_.resize(n);
  // One camera per task (the reader keeps one video decoder per camera): a
  // dome's plates or medians are most of the start-up otherwise.
  std::vector<Status> errors(n);
  pool->Run(uint32_t(n), [&](uint32_t c) {
    if (capture.cameras[c].background) {
      StatusOr<Image> plate = reader.ReadBackground(c);
      if (!plate.ok()) {
        errors[c] = plate.status();
        return;
      }
      f->backgrounds_[c].colour = std::move(*plate);
      return;
    }
    // No plate: the temporal median of up to 15 frames spread over the take.
    std::vector<Image> samples;
    const uint32_t count = std::min<uint32_t>(15, capture.frame_count);
    for (uint32_t k = 0; k < count; ++k) {
      const uint32_t frame =
          uint32_t(uint64_t(k) * (capture.frame_count - 1) / std::max(1u, count - 1));
      StatusOr<Image> image = reader.ReadFrame(c, frame);
      if (!image.ok()) {
        errors[c] = image.status();
        return;
      }
      samples.push_back(std::move(*image));
    }
    f->backgrounds_[c].colour = TemporalMedian(samples);
  });
  for (const Status& s : errors) FVV_RETURN_IF_ERROR(s);
  return f;
}

Status CaptureFrames::Read(uint32_t frame, std::vector<Image>* images,
                           std::vector<Image>* silhouettes) {
  if (persons_) return ReadWithPersons(frame, images, silhouettes);
  const uint32_t n = uint32_t(capture().cameras.size());
  silhouettes->assign(n, Image());
  std::vector<Image> read(n);
  if (images || !given_) FVV_RETURN_IF_ERROR(DecodeFrame(frame, &read));
  std::vector<Status> errors(n);
  // One camera per task: the reader keeps one video decoder per camera.
  pool_->Run(n, [&](uint32_t c) {
    StatusOr<Image> s =
        given_ ? reader_.ReadSilhouette(c, frame) : ExtractSilhouette(read[c], backgrounds_[c]);
    if (!s.ok()) {
      errors[c] = s.status();
      return;
    }
    (*silhouettes)[c] = std::move(*s);
  });
  for (const Status& s : errors) FVV_RETURN_IF_ERROR(s);
  if (images) *images = std::move(read);
  return Status::Ok();
}

CaptureFrames::~CaptureFrames() {
  if (ahead_.valid()) ahead_.wait();
}

void CaptureFrames::Prefetch(uint32_t frame) {
  if (given_) return;  // the silhouettes are read, not made from the images
  if (ahead_.valid()) ahead_.wait();
  ahead_frame_ = frame;
  ahead_ = std::async(std::launch::async, [this, frame] {
    std::vector<StatusOr<Image>> images;
    for (uint32_t c = 0; c < capture().cameras.size(); ++c) {
      images.push_back(reader_.ReadFrame(c, frame));
    }
    return images;
  });
}

Status CaptureFrames::DecodeFrame(uint32_t frame, std::vector<Image>* read) {
  const uint32_t n = uint32_t(capture().cameras.size());
  read->assign(n, Image());
  if (ahead_.valid()) {
    std::vector<StatusOr<Image>> images = ahead_.get();
    if (ahead_frame_ == frame) {
      for (uint32_t c = 0; c < n; ++c) {
        if (!images[c].ok()) return images[c].status();
        (*read)[c] = std::move(*images[c]);
      }
      return Status::Ok();
    }
  }
  std::vector<Status> errors(n);
  pool_->Run(n, [&](uint32_t c) {
    StatusOr<Image> image = reader_.ReadFrame(c, frame);
    if (image.ok()) {
      (*read)[c] = std::move(*image);
    } else {
      errors[c] = image.status();
    }
  });
  for (const Status& s : errors) FVV_RETURN_IF_ERROR(s);
  return Status::Ok();
}

std::string CaptureFrames::silhouette_source() const {
  if (given_) return "given";
  if (persons_) return plates_ ? "person masks and background subtraction" : "person masks";
  return "background subtraction";
}

Status CaptureFrames::ReadWithPersons(uint32_t frame, std::vector<Image>* images,
                                      std::vector<Image>* silhouettes) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  const uint32_t n = uint32_t(capture().cameras.size());
  std::vector<Image> read;
  FVV_RETURN_IF_ERROR(DecodeFrame(frame, &read));
  std::vector<Status> errors(n);
  const auto decoded = Clock::now();
  decode_seconds_ += std::chrono::duration<double>(decoded - start).count();
  auto named = [&](uint32_t c, const Status& s) {
    return Status(s.code(), "camera " + capture().cameras[c].calibration.name + ": " + s.message());
  };
  // Cameras that follow the actor look where it was; the others detect
  // everyone, and the person whose hips agree in 3D with the followed cameras
  // (or, with none, across the detecting ones) is taken as the actor.
  std::vector<PersonObservation> seen(n);
  std::vector<std::optional<HipSighting>> known(n);
  std::vector<std::vector<PersonObserver::Candidate>> candidates(n);
  bool detect = false;
  for (uint32_t c = 0; c < n; ++c) {
    if (regions_[c].size > 0) {
      StatusOr<PersonObservation> o = persons_->ObserveRegion(read[c], regions_[c]);
      if (!o.ok()) return named(c, o.status());
      seen[c] = std::move(*o);
    }
    if (seen[c].found) {
      known[c] = HipSighting{0.5 * (seen[c].keypoints[23].pixel + seen[c].keypoints[24].pixel),
                             kHipTolerance * seen[c].region.size};
      continue;
    }
    StatusOr<std::vector<PersonObserver::Candidate>> people = persons_->Detect(read[c]);
    if (!people.ok()) return named(c, people.status());
    candidates[c] = std::move(*people);
    detect = detect || !candidates[c].empty();
  }
  if (detect) {
    std::vector<Camera> cameras;
    std::vector<std::vector<HipSighting>> hips(n);
    for (uint32_t c = 0; c < n; ++c) {
      cameras.push_back(capture().cameras[c].calibration);
      for (const PersonObserver::Candidate& p : candidates[c]) {
        hips[c].push_back({p.hips, kHipTolerance * p.region.size});
      }
    }
    const ActorChoice choice = ChooseActor(cameras, hips, known);
    for (uint32_t c = 0; c < n; ++c) {
      if (candidates[c].empty()) continue;
      // No two cameras agree (one camera, or the actor seen once): the most
      // confident person, as a single camera would.
      const int pick = choice.hips ? choice.chosen[c] : 0;
      if (pick < 0) continue;
      StatusOr<PersonObservation> o = persons_->ObserveRegion(read[c], candidates[c][pick].region);
      if (!o.ok()) return named(c, o.status());
      seen[c] = std::move(*o);
      seen[c].detected = true;
    }
  }
  person_seconds_ += std::chrono::duration<double>(Clock::now() - decoded).count();
  silhouettes->assign(n, Image());
  sightings_.assign(n, {});
  pool_->Run(n, [&](uint32_t c) {
    regions_[c] = seen[c].found ? seen[c].next : PersonRegion();
    if (keep_sightings_) sightings_[c] = BodyJointSightings(seen[c]);
    Image& s = (*silhouettes)[c];
    s.width = read[c].width;
    s.height = read[c].height;
    s.channels = 1;
    s.pixels.assign(size_t{s.width} * s.height, 0);
    if (!seen[c].found) return;
    // Half the network's probability, as a mask; holes and specks cleaned as
    // background subtraction's are.
    for (size_t i = 0; i < s.pixels.size(); ++i)
      s.pixels[i] = seen[c].mask.pixels[i] > 127 ? 255 : 0;
    CleanMask(&s, SilhouetteParams());
    if (!plates_) return;
    // With plates: background subtraction's edges at full resolution, within
    // eight of the network's mask cells (256 across its region) of its edge:
    // the mask is off by that much in places.
    StatusOr<Image> subtracted = ExtractSilhouette(read[c], backgrounds_[c]);
    if (!subtracted.ok()) {
      errors[c] = subtracted.status();
      return;
    }
    RefineMaskEdges(&s, *subtracted, int(std::ceil(8 * seen[c].region.size / 256)));
  });
  for (const Status& s : errors) FVV_RETURN_IF_ERROR(s);
  // The sides' agreement tries cameras against each other: only for a fit.
  if (keep_sightings_) {
    side_exchanges_ += uint32_t(ExchangeMislabelledSides(cameras_, &sightings_).exchanges.size());
  }
  if (images) *images = std::move(read);
  return Status::Ok();
}

StatusOr<CaptureSightings> ReadSightings(const Capture& capture, PersonObserver* persons,
                                         uint32_t first, uint32_t last,
                                         const std::function<void(const std::string&)>& progress) {
  if (!persons) return InvalidArgument("joint sightings need the person network");
  if (first > last || last >= capture.frame_count) {
    return InvalidArgument("frames " + std::to_string(first) + ".." + std::to_string(last) +
                           ": the capture has " + std::to_string(capture.frame_count));
  }
  ThreadPool pool(2);
  StatusOr<std::unique_ptr<CaptureFrames>> frames =
      CaptureFrames::Open(capture, false, &pool, persons);
  if (!frames.ok()) return frames.status();
  CaptureSightings seen;
  for (uint32_t f = first; f <= last; ++f) {
    std::vector<Image> silhouettes;
    FVV_RETURN_IF_ERROR((*frames)->Read(f, nullptr, &silhouettes));
    seen.push_back((*frames)->sightings());
    if (progress && (f - first) % 10 == 9) {
      progress("keypoints of frame " + std::to_string(f) + " (" + std::to_string(f - first + 1) +
               "/" + std::to_string(last - first + 1) + ")");
    }
  }
  return seen;
}

}  // namespace fvv
