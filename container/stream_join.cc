#include "container/stream_join.h"

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <map>
#include <memory>

#include "container/body_model.h"
#include "container/cameras.h"
#include "container/file_reader.h"
#include "container/writer.h"

namespace fvv {
namespace {

bool ParseU32(const std::string& text, uint32_t* out) {
  if (text.empty() || text.size() > 10) return false;
  for (char c : text) {
    if (c < '0' || c > '9') return false;
  }
  const unsigned long long v = std::strtoull(text.c_str(), nullptr, 10);
  if (v > UINT32_MAX) return false;
  *out = uint32_t(v);
  return true;
}

bool IsShardKey(const std::string& key) {
  return key == kShardKey || key == kShardTakeFramesKey || key == kShardFirstFrameKey;
}

struct Part {
  std::string path;
  std::unique_ptr<FileSource> source;
  std::unique_ptr<FileReader> reader;
  ShardPosition position;
};

std::string FrameRange(uint32_t first, uint32_t count) {
  return "frames " + std::to_string(first) + ".." + std::to_string(first + count - 1);
}

// What differs between the header of `p` and that of the first part, or "".
std::string HeaderDifference(const FileHeader& a, const FileHeader& b) {
  if (a.tools != b.tools) return "coding tools";
  if (a.format_version != b.format_version) return "format version";
  if (a.profile != b.profile) return "profile";
  if (a.level != b.level) return "level";
  if (a.frame_rate_num != b.frame_rate_num || a.frame_rate_den != b.frame_rate_den) {
    return "frame rate";
  }
  if (a.camera_count != b.camera_count) return "camera count";
  if (a.atlas_width != b.atlas_width || a.atlas_height != b.atlas_height) return "atlas size";
  if (a.gop_frames != b.gop_frames || a.gop_cameras != b.gop_cameras) return "GOP size";
  return "";
}

std::string MotionDifference(const MotionParams& a, const MotionParams& b) {
  if (a.rotation_step != b.rotation_step) return "motion rotation step";
  if (a.translation_step_um != b.translation_step_um) return "motion translation step";
  if (a.coder != b.coder) return "motion coder";
  if (a.key_interval != b.key_interval) return "motion key interval";
  return "";
}

bool SameStatistics(const MotionParams& a, const MotionParams& b) {
  return a.key_reference == b.key_reference && a.first_class == b.first_class &&
         a.context_init == b.context_init;
}

Status CheckAgreement(const std::vector<Part>& parts) {
  const Part& ref = parts[0];
  const StreamInfo& r = ref.reader->info();
  const std::vector<uint8_t> cameras = WriteCamerasBox(r.cameras);
  const std::vector<uint8_t> model = WriteModelBox(r.model);
  const Metadata metadata = WithoutShardKeys(r.metadata);
  uint32_t next = 0;
  for (const Part& p : parts) {
    const StreamInfo& i = p.reader->info();
    const std::string who = p.path + " (part " + std::to_string(p.position.index) + " of " +
                            std::to_string(p.position.count) + ")";
    std::string diff = HeaderDifference(i.header, r.header);
    if (diff.empty()) diff = MotionDifference(i.motion, r.motion);
    if (diff.empty() && WriteCamerasBox(i.cameras) != cameras) diff = "cameras";
    if (diff.empty() && WriteModelBox(i.model) != model) diff = "body model";
    if (diff.empty() && WithoutShardKeys(i.metadata) != metadata) diff = "metadata";
    if (diff.empty() && p.position.take_frames != ref.position.take_frames) diff = "take's frames";
    if (!diff.empty()) {
      return InvalidArgument(who + ": its " + diff + " differs from " + ref.path +
                             "'s: the parts are not shards of one encode");
    }
    const uint32_t frames = i.header.frame_count;
    if (frames == 0) return InvalidArgument(who + ": a live stream (no frame count) is no shard");
    if (p.position.first != next) {
      return InvalidArgument(who + " starts at frame " + std::to_string(p.position.first) +
                             " of the take, not " + std::to_string(next) +
                             " where the part before it ends");
    }
    next += frames;
    const bool last = &p == &parts.back();
    if (!last && frames % i.header.gop_frames != 0) {
      return InvalidArgument(who + " has " + std::to_string(frames) +
                             " frames, not a whole number of GOPs of " +
                             std::to_string(i.header.gop_frames));
    }
  }
  if (next != ref.position.take_frames) {
    return InvalidArgument("the parts hold " + std::to_string(next) + " frames of a take of " +
                           std::to_string(ref.position.take_frames));
  }
  return Status::Ok();
}

// Every part's decoded poses, in take order (key interval 1: every frame carries its values).
StatusOr<std::vector<QuantisedPose>> TakePoses(std::vector<Part>& parts) {
  std::vector<QuantisedPose> poses;
  for (Part& p : parts) {
    const StreamInfo& info = p.reader->info();
    for (size_t k = 0; k < p.reader->fragment_count(); ++k) {
      if (info.index[k].first_camera != 0) continue;  // the motion is in camera group 0's
      StatusOr<FragmentData> f = p.reader->ReadFragment(k);
      if (!f.ok()) return Status(f.status().code(), p.path + ": " + f.status().message());
      if (f->motion.empty()) return Corrupt(p.path + ": a fragment without its motion track");
      std::vector<DecodedFrame> frames;
      const Status s = DecodeMotion(MotionBoxHeader(*f), f->motion.data(), info.model.skeleton,
                                    info.motion, f->info.frame_count, &frames);
      if (!s.ok()) return Status(s.code(), p.path + ": " + s.message());
      for (const DecodedFrame& d : frames) poses.push_back(d.values);
    }
  }
  return poses;
}

}  // namespace

Metadata ShardMetadata(const ShardPosition& p) {
  return {{kShardKey, std::to_string(p.index) + "/" + std::to_string(p.count)},
          {kShardTakeFramesKey, std::to_string(p.take_frames)},
          {kShardFirstFrameKey, std::to_string(p.first)}};
}

StatusOr<ShardPosition> ReadShardPosition(const Metadata& metadata, const std::string& what) {
  std::map<std::string, std::string> keys;
  for (const auto& [k, v] : metadata) {
    if (IsShardKey(k)) keys[k] = v;
  }
  if (!keys.count(kShardKey)) {
    return InvalidArgument(what + " is not a shard (no " + kShardKey +
                           " metadata: fvv encode --shard K/N writes it)");
  }
  ShardPosition p;
  const std::string& kn = keys[kShardKey];
  const size_t slash = kn.find('/');
  if (slash == std::string::npos || !ParseU32(kn.substr(0, slash), &p.index) ||
      !ParseU32(kn.substr(slash + 1), &p.count) || p.count == 0 || p.index >= p.count ||
      !keys.count(kShardTakeFramesKey) || !ParseU32(keys[kShardTakeFramesKey], &p.take_frames) ||
      !keys.count(kShardFirstFrameKey) || !ParseU32(keys[kShardFirstFrameKey], &p.first)) {
    return InvalidArgument(what + ": malformed shard metadata (" + kShardKey + " \"" + kn + "\")");
  }
  return p;
}

Metadata WithoutShardKeys(const Metadata& metadata) {
  Metadata out;
  for (const auto& kv : metadata) {
    if (!IsShardKey(kv.first)) out.push_back(kv);
  }
  return out;
}

StatusOr<JoinSummary> JoinShards(const std::vector<std::string>& paths, const std::string& output,
                                 const std::function<void(const std::string&)>& progress) {
  if (paths.empty()) return InvalidArgument("no parts to join");
  std::vector<Part> parts;
  for (const std::string& path : paths) {
    if (path == output) return InvalidArgument(path + " is both a part and the output");
    Part p;
    p.path = path;
    FVV_ASSIGN_OR_RETURN(p.source, FileSource::Open(path));
    StatusOr<std::unique_ptr<FileReader>> reader = FileReader::Open(p.source.get());
    if (!reader.ok()) {
      return Status(reader.status().code(), path + ": " + reader.status().message());
    }
    p.reader = std::move(reader).value();
    FVV_ASSIGN_OR_RETURN(p.position, ReadShardPosition(p.reader->info().metadata, path));
    parts.push_back(std::move(p));
  }
  std::sort(parts.begin(), parts.end(),
            [](const Part& a, const Part& b) { return a.position.index < b.position.index; });
  const uint32_t n = parts[0].position.count;
  std::vector<const Part*> by_index(n, nullptr);
  for (const Part& p : parts) {
    if (p.position.count != n) {
      return InvalidArgument(p.path + " is a part of " + std::to_string(p.position.count) +
                             " shards, " + parts[0].path + " of " + std::to_string(n));
    }
    if (by_index[p.position.index]) {
      return InvalidArgument(p.path + " and " + by_index[p.position.index]->path +
                             " are both part " + std::to_string(p.position.index));
    }
    by_index[p.position.index] = &p;
  }
  for (uint32_t k = 0; k < n; ++k) {
    if (!by_index[k]) {
      return InvalidArgument("part " + std::to_string(k) + " of " + std::to_string(n) +
                             " is missing (fvv encode --shard " + std::to_string(k) + "/" +
                             std::to_string(n) + " writes it)");
    }
  }
  FVV_RETURN_IF_ERROR(CheckAgreement(parts));

  const StreamInfo& first = parts[0].reader->info();
  StreamInfo info;
  info.header = first.header;
  info.header.frame_count = parts[0].position.take_frames;
  info.header.index_offset = 0;
  info.cameras = first.cameras;
  info.model = first.model;
  info.motion = first.motion;
  info.metadata = WithoutShardKeys(first.metadata);
  JoinSummary sum;
  sum.parts = n;
  sum.frames = info.header.frame_count;

  // The motion statistics of the whole take, as one encode measures them.
  bool shared = true;
  for (const Part& p : parts)
    shared = shared && SameStatistics(p.reader->info().motion, first.motion);
  std::vector<QuantisedPose> poses;
  if (!shared) {
    if (first.motion.key_interval != 1) {
      return InvalidArgument(
          "the parts' motion statistics differ and their key interval is " +
          std::to_string(first.motion.key_interval) +
          ": interpolated frames carry no values to measure the take's again (encode shards "
          "with key interval 1)");
    }
    FVV_ASSIGN_OR_RETURN(poses, TakePoses(parts));
    TrainMotionParams(info.model.skeleton, poses, info.header.gop_frames, &info.motion);
    sum.motion_recoded = true;
  }

  FVV_ASSIGN_OR_RETURN(std::unique_ptr<FileWriter> writer, FileWriter::Create(output, info));
  const uint32_t groups = info.header.camera_groups();
  for (Part& p : parts) {
    const uint32_t span_offset = p.position.first / info.header.gop_frames;
    for (size_t k = 0; k < p.reader->fragment_count(); ++k) {
      StatusOr<FragmentData> f = p.reader->ReadFragment(k);
      if (!f.ok()) return Status(f.status().code(), p.path + ": " + f.status().message());
      f->info.gop_index += span_offset * groups;
      f->info.first_frame += p.position.first;
      if (sum.motion_recoded && f->info.first_camera == 0) {
        const std::vector<QuantisedPose> span(
            poses.begin() + f->info.first_frame,
            poses.begin() + f->info.first_frame + f->info.frame_count);
        FVV_ASSIGN_OR_RETURN(f->motion, EncodeMotion(info.model.skeleton, info.motion, span));
      }
      FVV_RETURN_IF_ERROR(writer->AddFragment(*f));
      ++sum.fragments;
    }
    if (progress) {
      progress("join: " + p.path + " (" +
               FrameRange(p.position.first, p.reader->info().header.frame_count) + ")");
    }
  }
  FVV_RETURN_IF_ERROR(writer->Close());
  sum.bytes = writer->bytes_written();
  return sum;
}

}  // namespace fvv
