#include "encoder/encode/encoder.h"

#include <algorithm>

#include "container/stream_join.h"
#include "container/surface_displacement.h"
#include "encoder/capture/colour_gain.h"
#include "encoder/encode/encoder_session.h"

namespace fvv {
namespace encoding {

Status CheckSettings(const EncoderSettings& s) {
  if (s.atlas_size < 16 || s.atlas_size > 4096) {
    return InvalidArgument("atlas size " + std::to_string(s.atlas_size) + " is not in 16..4096");
  }
  if (s.gop_frames < 1) return InvalidArgument("GOP frames must be >= 1");
  if (!ValidFracBits97(s.frac_bits_97)) {
    return InvalidArgument("9/7 sample precision " + std::to_string(s.frac_bits_97) +
                           " is not in " + std::to_string(kMinFracBits97) + ".." +
                           std::to_string(kMaxFracBits97) + " fractional bits");
  }
  if (s.texture_codec == TextureCodec::kPredictive) {
    if (!s.masks) {
      return InvalidArgument(
          "the predictive texture codec needs masks (they are its supports): code them");
    }
    if (s.chroma != ChromaFormat::k444) {
      return InvalidArgument("the predictive texture codec codes 4:4:4 only");
    }
  }
  if (!s.poses.empty() && !s.textures.empty()) {
    return InvalidArgument("give poses or textures, not both (textures carry their poses)");
  }
  if (!s.save_textures.empty() && !s.textures.empty()) {
    return InvalidArgument("--save-textures with --textures would copy the input");
  }
  if (!std::isfinite(s.rate_value) || s.rate_value <= 0) {
    return InvalidArgument("the rate (bpp, bytes or PSNR) must be positive");
  }
  if (s.threads < 1 || s.threads > 256) return InvalidArgument("threads must be 1..256");
  if (s.surface) {
    if (!s.texture_chunks || s.texture_codec == TextureCodec::kPredictive) {
      return InvalidArgument(
          "the surface travels in the texture's chunks: not with --whole-texture or the "
          "predictive codec");
    }
    if (!s.textures.empty()) {
      return InvalidArgument("the surface is tracked from silhouettes: not with --textures");
    }
    if (s.surface_step_exponent < kMinSurfaceStepExponent ||
        s.surface_step_exponent > kMaxSurfaceStepExponent) {
      return InvalidArgument("surface step exponent " + std::to_string(s.surface_step_exponent) +
                             " is not in " + std::to_string(kMinSurfaceStepExponent) + ".." +
                             std::to_string(kMaxSurfaceStepExponent));
    }
  }
  if (s.shards > 0) {
    if (s.shard >= s.shards) {
      return InvalidArgument("shard " + std::to_string(s.shard) + "/" + std::to_string(s.shards) +
                             ": K counts from 0 and must be below N");
    }
    if (s.prepared.empty()) {
      return InvalidArgument("--shard needs --prepared DIR (fvv encode --prepare DIR writes it)");
    }
    if (s.key_interval != 1) {
      // Interpolated frames carry no values, so the join could not measure
      // the take's motion statistics again.
      return InvalidArgument("shards are coded with motion key interval 1");
    }
  }
  if (!s.after.empty() && (s.shards == 0 || s.shard == 0 || !s.poses.empty())) {
    return InvalidArgument(
        "--after goes with --shard K/N (K above 0) of a take prepared without poses");
  }
  if (!s.prepared.empty()) {
    if (!s.textures.empty()) {
      return InvalidArgument("--prepared with --textures: the prepared take resamples its frames");
    }
    if (s.first_frame != 0 || s.last_frame != UINT32_MAX) {
      return InvalidArgument("--frames with --prepared: the prepared take sets the frames");
    }
    if (s.refine_shape) {
      return InvalidArgument("--refine-shape belongs to --prepare: the prepared model is used");
    }
  }
  return Status::Ok();
}

}  // namespace encoding

namespace {

using encoding::CheckSettings;
using encoding::Clock;
using encoding::FrameSpan;
using encoding::FramesToEncode;
using encoding::Session;
using encoding::Since;
using encoding::TakeFeatures;

void Say(const EncoderSettings& s, const std::string& line) {
  if (s.progress) s.progress(line);
}

}  // namespace

namespace encoding {

StatusOr<FrameSpan> FramesToEncode(const Capture& cap, const EncoderSettings& s,
                                   const PoseSequence* given) {
  FrameSpan r{s.first_frame, std::min(s.last_frame, cap.frame_count - 1)};
  if (given) {
    r.first = std::max(r.first, given->first_frame);
    r.last = std::min<uint32_t>(r.last, given->first_frame + uint32_t(given->poses.size()) - 1);
  }
  if (r.first > r.last) {
    return InvalidArgument(
        "no frames to encode: frames " + std::to_string(s.first_frame) + ".." +
        (s.last_frame == UINT32_MAX ? std::string("end") : std::to_string(s.last_frame)) +
        " of a capture of " + std::to_string(cap.frame_count) +
        (given ? " with poses for frames " + std::to_string(given->first_frame) + ".." +
                     std::to_string(given->first_frame + given->poses.size() - 1)
               : std::string()));
  }
  return r;
}

StatusOr<TextureFrames> OpenTextureFrames(const Capture& cap, const EncoderSettings& s,
                                          ThreadPool* pool, std::string* note) {
  TextureFrames t;
  FVV_ASSIGN_OR_RETURN(
      t.persons, PersonsForCapture(cap, s.extract_silhouettes, s.persons, s.person_models, note));
  FVV_ASSIGN_OR_RETURN(t.frames,
                       CaptureFrames::Open(cap, s.extract_silhouettes, pool, t.persons.get()));
  t.frames->SkipSightings();
  return t;
}

StatusOr<TakeFeatures> TakeFeatures::Load(const Capture& cap, const std::string& path) {
  TakeFeatures t;
  for (const auto& c : cap.cameras) t.cameras_.push_back(c.calibration);
  if (path.empty()) return t;
  StatusOr<FeatureSet> f = LoadFeatures(path, t.cameras_, cap.frame_count);
  if (!f.ok()) return f.status();
  t.features_ = std::move(*f);
  return t;
}

std::map<std::string, Eigen::Vector3d> TakeFeatures::Of(uint32_t frame) const {
  std::map<std::string, Eigen::Vector3d> out;
  if (!features_.frames.count(frame)) return out;
  for (const auto& [name, p] : TriangulateFeatures(features_.frames.at(frame), cameras_)) {
    out[name] = p.position;
  }
  return out;
}

}  // namespace encoding

StatusOr<EncodeSummary> EncodeCapture(const std::string& capture_path, const std::string& output,
                                      const EncoderSettings& s_in) {
  const auto start = Clock::now();
  FVV_RETURN_IF_ERROR(CheckSettings(s_in));
  StatusOr<Capture> cap = LoadCapture(capture_path);
  if (!cap.ok()) return cap.status();
  if (cap->cameras.size() > 65535) return InvalidArgument("more than 65535 cameras");
  EncoderSettings s = s_in;
  if (s.gop_cameras == 0) s.gop_cameras = uint16_t(cap->cameras.size());

  // Poses given (a file, or the textures' own record), or tracked below.
  std::optional<PoseSequence> given;
  if (!s.poses.empty() || !s.textures.empty()) {
    StatusOr<PoseSequence> p =
        LoadPoseFile(s.poses.empty() ? s.textures + "/textures.json" : s.poses);
    if (!p.ok()) return p.status();
    given = std::move(*p);
  }
  FVV_ASSIGN_OR_RETURN(const FrameSpan range, FramesToEncode(*cap, s, given ? &*given : nullptr));
  uint32_t first = range.first, last = range.last;
  std::optional<PreparedTake> prepared;
  if (!s.prepared.empty()) {
    StatusOr<PreparedTake> p = LoadPreparedTake(s.prepared);
    if (!p.ok()) return p.status();
    prepared = std::move(*p);
    if (prepared->shards_track && given) {
      return InvalidArgument(s.prepared +
                             " was prepared without poses, for shards that track: "
                             "leave out --poses");
    }
    if (!prepared->shards_track && !given) {
      return InvalidArgument("--prepared " + s.prepared +
                             " needs --poses: the poses the take was prepared with");
    }
    if (given && given->crc32c != prepared->poses_crc) {
      return InvalidArgument(s.poses + " is not the poses file " + s.prepared +
                             " was prepared with (its checksum differs)");
    }
    if (prepared->gop_frames != s.gop_frames) {
      return InvalidArgument(s.prepared + " was prepared for GOPs of " +
                             std::to_string(prepared->gop_frames) + " frames, not " +
                             std::to_string(s.gop_frames));
    }
    if (prepared->first_frame < first || prepared->last_frame > last) {
      return InvalidArgument(s.prepared + "'s frames " + std::to_string(prepared->first_frame) +
                             ".." + std::to_string(prepared->last_frame) +
                             " are not all in the capture and the poses");
    }
    first = prepared->first_frame;
    last = prepared->last_frame;
    if (s.shards > 0) {
      FVV_ASSIGN_OR_RETURN(const ShardFrames part,
                           ShardFramesOf(prepared->frames(), s.gop_frames, s.shard, s.shards));
      ShardPosition position;
      position.index = s.shard;
      position.count = s.shards;
      position.take_frames = prepared->frames();
      position.first = part.first;
      for (auto& kv : ShardMetadata(position)) s.metadata.push_back(kv);
      first = prepared->first_frame + part.first;
      last = first + part.count - 1;
    }
  }
  if (!s.textures.empty() && given->atlas_size != s.atlas_size) {
    // The textures must have been made for this atlas.
    return InvalidArgument(s.textures + "/textures.json: atlas_size is not " +
                           std::to_string(s.atlas_size) + " (pass --atlas to match)");
  }

  // Feature points for shape refinement's features term (optional).
  FVV_ASSIGN_OR_RETURN(const TakeFeatures features, TakeFeatures::Load(*cap, s.features));
  Session session(*cap, output, s, first, last);
  EncodeSummary& sum = session.summary();
  const size_t gained =
      size_t(std::count_if(cap->cameras.begin(), cap->cameras.end(),
                           [](const auto& c) { return !IsUnitGain(c.colour_gain); }));
  if (gained > 0 && s.textures.empty()) {
    Say(s, "encode: " + std::to_string(gained) + " camera(s) read through their colour_gain " +
               "(capture.json): the textures in the rig's common colour");
  }
  const uint32_t total = last - first + 1;
  auto progress = [&](uint32_t frame, const std::string& extra) {
    const uint32_t done = frame - first + 1;
    const double elapsed = Since(start);
    char line[256];
    std::snprintf(line, sizeof(line), "encode: frame %u (%u/%u)%s  %.2f s/frame, ETA %.0f s", frame,
                  done, total, extra.c_str(), elapsed / done, elapsed / done * (total - done));
    Say(s, line);
  };

  if (given) {
    sum.pose_source = s.textures.empty() ? "poses " + s.poses : "textures " + s.textures;
    encoding::TextureFrames texture_frames;
    CaptureFrames* frames = nullptr;
    if (s.textures.empty()) {
      std::vector<uint32_t> wanted;
      for (uint32_t f = first; f <= last; ++f) wanted.push_back(f);
      FVV_RETURN_IF_ERROR(CheckFramesPresent(*cap, wanted));
      std::string note;
      FVV_ASSIGN_OR_RETURN(texture_frames,
                           encoding::OpenTextureFrames(*cap, s, &session.pool(), &note));
      if (!note.empty()) Say(s, "encode: " + note);
      frames = texture_frames.frames.get();
      session.SetPersonMasks(frames->person_masks());
    } else if (s.refine_shape) {
      return InvalidArgument("--refine-shape needs the capture's images, not --textures");
    }
    for (uint32_t f = first; f <= last; ++f) {
      std::vector<Image> images, sils;
      if (frames) {
        const auto t0 = Clock::now();
        FVV_RETURN_IF_ERROR(frames->Read(f, &images, &sils));
        // The next frame decodes while this one is resampled and coded.
        if (f < last) frames->Prefetch(f + 1);
        sum.read_s += Since(t0);
      }
      if (f == first && prepared) {
        FVV_RETURN_IF_ERROR(session.UsePrepared(*prepared));
      } else if (f == first) {
        const RefinementFrame refine{given->poses[f - given->first_frame], images, sils,
                                     features.Of(f)};
        FVV_RETURN_IF_ERROR(session.SetShape(given->shape, frames ? &refine : nullptr));
      }
      FVV_RETURN_IF_ERROR(session.AddFrame(f, given->poses[f - given->first_frame], images, sils));
      progress(f, "");
    }
  } else {
    sum.pose_source = "tracked";
    TrackCaptureOptions to;
    to.first = first;
    to.last = last;
    to.tracker = s.tracker;
    to.extract = s.extract_silhouettes;
    to.persons = s.persons;
    to.person_models = s.person_models;
    to.smoothing = s.pose_smoothing;  // before GoOnAfter, which keeps what it reads
    if (prepared) {
      // A shard's warm-up frames and the take's shape, as every shard tracks.
      UsePreparedTracking(*prepared, first, last, &to);
      if (!s.after.empty()) FVV_RETURN_IF_ERROR(GoOnAfter(s.after, s.shard, s.shards, &to));
      sum.pose_source =
          "tracked (prepared take, " + std::to_string(prepared->warm_up) + " frames' warm-up)";
    }
    // Of a studio's many cameras the fit reads a chosen few; the texture is
    // then read from every camera as with poses given (OpenTextureFrames),
    // beside the tracking.
    std::string fit_names;
    const Capture fit_capture =
        FittingCapture(*cap, TrackingCameraCount(s.track_cameras, cap->cameras.size()), &fit_names);
    encoding::TextureFrames every_camera_frames;
    CaptureFrames* every_camera = nullptr;
    double texture_read_s = 0;
    if (fit_capture.cameras.size() < cap->cameras.size()) {
      if (s.refine_shape) {
        return InvalidArgument(
            "--refine-shape reads the fit's cameras: with --track-cameras fewer than the rig's, "
            "track first (fvv track) and encode with --poses");
      }
      Say(s, "encode: tracking with " + std::to_string(fit_capture.cameras.size()) + " of " +
                 std::to_string(cap->cameras.size()) + " cameras (--track-cameras): " + fit_names);
      FVV_ASSIGN_OR_RETURN(every_camera_frames,
                           encoding::OpenTextureFrames(*cap, s, &session.pool(), nullptr));
      every_camera = every_camera_frames.frames.get();
      session.SetPersonMasks(every_camera->person_masks());
    }
    // Resampling and coding a frame run on a thread of their own, beside the
    // tracking of the next frames (at most one GOP and a frame queued), in
    // frame order, so the output is what a sequential run writes.
    OrderedQueue behind_tracking(s.gop_frames + 1);
    if (!every_camera) {
      to.on_open = [&session](const CaptureFrames& f) { session.SetPersonMasks(f.person_masks()); };
    }
    to.on_frame = [&](uint32_t f, const FrameFit& fit, const Tracker& tracker,
                      const std::vector<Image>& images, const std::vector<Image>& sils) -> Status {
      if (!session.HasShape() && prepared) {
        FVV_RETURN_IF_ERROR(session.UsePrepared(*prepared));
      } else if (!session.HasShape()) {  // the shape: once, before any frame is resampled
        const RefinementFrame refine{fit.dofs, images, sils, features.Of(f)};
        FVV_RETURN_IF_ERROR(session.SetShape(tracker.shape(), every_camera ? nullptr : &refine));
      }
      char extra[96];
      std::snprintf(extra, sizeof(extra), "  IoU %.3f%s", fit.iou,
                    fit.poor ? ("  FLAGGED: " + fit.note).c_str() : "");
      if (every_camera) {
        return behind_tracking.Push([&session, &progress, &texture_read_s, every_camera, f, last,
                                     dofs = fit.dofs, line = std::string(extra)] {
          std::vector<Image> all_images, all_sils;
          const auto t0 = Clock::now();
          FVV_RETURN_IF_ERROR(every_camera->Read(f, &all_images, &all_sils));
          if (f < last) every_camera->Prefetch(f + 1);
          texture_read_s += Since(t0);
          FVV_RETURN_IF_ERROR(session.AddFrame(f, dofs, all_images, all_sils));
          progress(f, line);
          return Status::Ok();
        });
      }
      return behind_tracking.Push(
          [&session, &progress, f, dofs = fit.dofs, images, sils, line = std::string(extra)] {
            FVV_RETURN_IF_ERROR(session.AddFrame(f, dofs, images, sils));
            progress(f, line);
            return Status::Ok();
          });
    };
    StatusOr<TrackCaptureResult> tracked = TrackCapture(fit_capture, to);
    FVV_RETURN_IF_ERROR(behind_tracking.Finish());
    if (!tracked.ok()) return tracked.status();
    if (prepared && s.shards > 0 && !tracked->after_frames.empty()) {
      std::vector<uint32_t> take_frames;
      for (uint32_t f : tracked->after_frames) take_frames.push_back(f - prepared->first_frame);
      session.AddMetadata(kShardPosesAfterKey, FormatShardPoses(take_frames, tracked->after_poses));
    }
    sum.read_s = tracked->silhouette_seconds + texture_read_s;
    sum.track_s = tracked->fit_seconds;
    sum.flagged_frames = tracked->flagged;
    sum.mean_iou = tracked->mean_iou;
  }
  Say(s, "encode: writing " + output);
  FVV_RETURN_IF_ERROR(session.Finish(output));
  sum.total_s = Since(start);
  return sum;
}

}  // namespace fvv
