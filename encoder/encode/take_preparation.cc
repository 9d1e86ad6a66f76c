// PrepareTake: the shared pass before a take is encoded in shards.
#include <algorithm>
#include <map>
#include <optional>

#include "encoder/encode/encoder.h"
#include "encoder/encode/encoder_session.h"

namespace fvv {

using encoding::Clock;
using encoding::Since;

namespace {

// Frames tracked from the take's first for the actor's shape: initialisation,
// then as many as an actor with proportions of its own needs to have its
// arms' length fitted again.
uint32_t ShapeFrames(const TrackerOptions& t) {
  return 1 + uint32_t(std::max(0, t.arm_refit_frames) * std::max(1, t.arm_refit_spacing));
}

}  // namespace

StatusOr<PrepareSummary> PrepareTake(const std::string& capture_path, const std::string& directory,
                                     const EncoderSettings& s_in) {
  const auto start = Clock::now();
  if (!s_in.prepared.empty() || s_in.shards > 0) {
    return InvalidArgument("--prepare writes a prepared take: not with --prepared or --shard");
  }
  FVV_RETURN_IF_ERROR(encoding::CheckSettings(s_in));
  if (s_in.prepare_frames < 1) return InvalidArgument("the static texture needs a frame");
  StatusOr<Capture> cap = LoadCapture(capture_path);
  if (!cap.ok()) return cap.status();
  EncoderSettings s = s_in;
  s.fallback_texture = true;  // the session keeps a static texture
  if (s.gop_cameras == 0) s.gop_cameras = uint16_t(cap->cameras.size());
  const auto Say = [&](const std::string& line) {
    if (s.progress) s.progress(line);
  };
  // The poses: given, or (shards that track) the shape from the take's first
  // frames and each texture frame fitted on its own with it.
  std::optional<PoseSequence> given;
  if (!s.poses.empty()) {
    StatusOr<PoseSequence> p = LoadPoseFile(s.poses);
    if (!p.ok()) return p.status();
    given = std::move(*p);
  }
  FVV_ASSIGN_OR_RETURN(const encoding::FrameSpan range,
                       encoding::FramesToEncode(*cap, s, given ? &*given : nullptr));
  PrepareSummary sum;
  sum.directory = directory;
  sum.first_frame = range.first;
  sum.frames = range.last - range.first + 1;
  sum.gops = (sum.frames + s.gop_frames - 1) / s.gop_frames;
  // Frames spread evenly over the take, the first and last included.
  const uint32_t count = std::min(s.prepare_frames, sum.frames);
  for (uint32_t i = 0; i < count; ++i) {
    const uint64_t offset = count == 1 ? 0 : uint64_t(i) * (sum.frames - 1) / (count - 1);
    sum.texture_frames.push_back(range.first + uint32_t(offset));
  }
  BodyShape shape;
  std::map<uint32_t, std::vector<double>> poses;
  if (given) {
    shape = given->shape;
    for (uint32_t f : sum.texture_frames) poses[f] = given->poses[f - given->first_frame];
  } else {
    // The cameras the shards' fits read (the shape is theirs).
    const Capture fit =
        FittingCapture(*cap, TrackingCameraCount(s.track_cameras, cap->cameras.size()));
    TrackCaptureOptions to;
    to.first = range.first;
    to.last = std::min(range.last, range.first + ShapeFrames(s.tracker) - 1);
    to.extract = s.extract_silhouettes;
    to.persons = s.persons;
    to.person_models = s.person_models;
    to.tracker = s.tracker;
    to.smoothing = s.pose_smoothing;
    Say("prepare: the actor's shape, tracking frames " + std::to_string(to.first) + ".." +
        std::to_string(to.last));
    FVV_ASSIGN_OR_RETURN(const TrackCaptureResult first_frames, TrackCapture(fit, to));
    shape = first_frames.shape;
    // Texture frames among those just tracked keep their tracked poses (a fit
    // too poor to trust would paint the actor's colours elsewhere); the others
    // are fitted each on its own with the shape.
    std::string note;
    const auto Take = [&](const TrackCaptureResult& r) {
      for (size_t i = 0; i < r.fits.size(); ++i) {
        const uint32_t f = r.frames[i];
        if (!std::binary_search(sum.texture_frames.begin(), sum.texture_frames.end(), f)) continue;
        if (r.fits[i].poor) {
          note = r.fits[i].note;
        } else {
          poses[f] = r.fits[i].dofs;
        }
      }
    };
    Take(first_frames);
    to.tracker.fixed_shape = shape;
    for (uint32_t f : sum.texture_frames) {
      if (f > first_frames.last) to.separate_frames.push_back(f);
    }
    if (!to.separate_frames.empty()) {
      Say("prepare: fitting " + std::to_string(to.separate_frames.size()) +
          " of the static texture's frames, each on its own");
      FVV_ASSIGN_OR_RETURN(const TrackCaptureResult spread, TrackCapture(fit, to));
      Take(spread);
    }
    if (poses.empty()) {
      return InvalidArgument("prepare: no frame of the static texture fits well enough (" + note +
                             ")");
    }
    sum.texture_frames.clear();
    for (const auto& kv : poses) sum.texture_frames.push_back(kv.first);
  }
  FVV_ASSIGN_OR_RETURN(const encoding::TakeFeatures features,
                       encoding::TakeFeatures::Load(*cap, s.features));
  encoding::Session session(*cap, "", s, range.first, range.last);
  // The static texture's frames, read as the shards' textures will be.
  FVV_ASSIGN_OR_RETURN(encoding::TextureFrames texture_frames,
                       encoding::OpenTextureFrames(*cap, s, &session.pool(), nullptr));
  CaptureFrames* const frames = texture_frames.frames.get();
  session.SetPersonMasks(frames->person_masks());
  const auto PoseOf = [&](uint32_t f) { return poses.at(f); };

  for (uint32_t f : sum.texture_frames) {
    std::vector<Image> images, sils;
    FVV_RETURN_IF_ERROR(frames->Read(f, &images, &sils));
    if (!session.HasShape()) {
      Say(std::string("prepare: the body model") +
          (s.refine_shape ? ", refined on frame " + std::to_string(f) : std::string()));
      const RefinementFrame refine{PoseOf(f), images, sils, features.Of(f)};
      FVV_RETURN_IF_ERROR(session.SetShape(shape, &refine));
    }
    FVV_RETURN_IF_ERROR(session.AddStaticFrame(f, PoseOf(f), images, sils));
    Say("prepare: static texture, frame " + std::to_string(f));
  }

  PreparedTake take;
  take.first_frame = range.first;
  take.last_frame = range.last;
  take.atlas_size = s.atlas_size;
  take.gop_frames = s.gop_frames;
  take.refined = s.refine_shape;
  take.poses_crc = given ? given->crc32c : 0;
  take.shards_track = !given;
  take.warm_up = given ? 0 : s.track_warm_up;
  take.texture_frames = sum.texture_frames;
  take.shape = session.shape();
  take.model = session.model();
  take.static_rgb = session.static_texture()->Rgb();
  take.static_coverage = session.static_texture()->Coverage();
  FVV_RETURN_IF_ERROR(WritePreparedTake(directory, take));
  sum.seconds = Since(start);
  return sum;
}

}  // namespace fvv
