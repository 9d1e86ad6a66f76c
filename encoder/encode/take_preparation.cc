// PrepareTake: the shared pass before a take is encoded in shards.
#include "encoder/encode/encoder.h"
#include "encoder/encode/encoder_session.h"

namespace fvv {

using encoding::Clock;
using encoding::Since;

StatusOr<PrepareSummary> PrepareTake(const std::string& capture_path, const std::string& directory,
                                     const EncoderSettings& s_in) {
  const auto start = Clock::now();
  if (s_in.poses.empty()) {
    return InvalidArgument(
        "--prepare needs --poses: the take's poses, from one tracking pass shared by all "
        "shards (fvv track)");
  }
  if (!s_in.prepared.empty() || s_in.shards > 0) {
    return InvalidArgument("--prepare writes a prepared take: not with --prepared or --shard");
  }
  FVV_RETURN_IF_ERROR(encoding::CheckSettings(s_in));
  if (s_in.prepare_frames < 1) return InvalidArgument("the static texture needs a frame");
  StatusOr<Capture> cap = LoadCapture(capture_path);
  if (!cap.ok()) return cap.status();
  StatusOr<PoseSequence> given = LoadPoseFile(s_in.poses);
  if (!given.ok()) return given.status();
  EncoderSettings s = s_in;
  s.fallback_texture = true;  // the session keeps a static texture
  if (s.gop_cameras == 0) s.gop_cameras = uint16_t(cap->cameras.size());
  FVV_ASSIGN_OR_RETURN(const encoding::FrameSpan range, encoding::FramesToEncode(*cap, s, &*given));
  FVV_ASSIGN_OR_RETURN(const encoding::TakeFeatures features,
                       encoding::TakeFeatures::Load(*cap, s.features));
  encoding::Session session(*cap, "", s, range.first, range.last);
  StatusOr<std::unique_ptr<CaptureFrames>> frames =
      CaptureFrames::Open(*cap, s.extract_silhouettes, &session.pool());
  if (!frames.ok()) return frames.status();
  const auto PoseOf = [&](uint32_t f) { return given->poses[f - given->first_frame]; };
  const auto Say = [&](const std::string& line) {
    if (s.progress) s.progress(line);
  };

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
  for (uint32_t f : sum.texture_frames) {
    std::vector<Image> images, sils;
    FVV_RETURN_IF_ERROR((*frames)->Read(f, &images, &sils));
    if (!session.HasShape()) {
      Say(std::string("prepare: the body model") +
          (s.refine_shape ? ", refined on frame " + std::to_string(f) : std::string()));
      const RefinementFrame refine{PoseOf(f), images, sils, features.Of(f)};
      FVV_RETURN_IF_ERROR(session.SetShape(given->shape, &refine));
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
  take.poses_crc = given->crc32c;
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
