#include "container/stream_join.h"

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <sstream>

#include "container/body_model.h"
#include "container/cameras.h"
#include "container/file_reader.h"
#include "container/fixed_rotation.h"
#include "container/motion_track.h"
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
  return key == kShardKey || key == kShardTakeFramesKey || key == kShardFirstFrameKey ||
         key == kShardPosesAfterKey;
}

struct Part {
  std::string path;
  std::unique_ptr<FileSource> source;
  std::unique_ptr<FileReader> reader;
  ShardPosition position;
};

// A part opened, with its place in the take from its metadata.
StatusOr<Part> OpenPart(const std::string& path) {
  Part p;
  p.path = path;
  FVV_ASSIGN_OR_RETURN(p.source, FileSource::Open(path));
  StatusOr<std::unique_ptr<FileReader>> reader = FileReader::Open(p.source.get());
  if (!reader.ok()) return Status(reader.status().code(), path + ": " + reader.status().message());
  p.reader = std::move(reader).value();
  FVV_ASSIGN_OR_RETURN(p.position, ReadShardPosition(p.reader->info().metadata, path));
  return p;
}

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

// A part's decoded poses, in frame order (key interval 1: every frame carries its values).
Status AppendPartPoses(Part& p, std::vector<QuantisedPose>* poses) {
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
    for (const DecodedFrame& d : frames) poses->push_back(d.values);
  }
  return Status::Ok();
}

// Every part's decoded poses, in take order.
StatusOr<std::vector<QuantisedPose>> TakePoses(std::vector<Part>& parts) {
  std::vector<QuantisedPose> poses;
  for (Part& p : parts) FVV_RETURN_IF_ERROR(AppendPartPoses(p, &poses));
  return poses;
}

// Parses kShardPosesAfterKey's value; false when malformed.
bool ParseShardPoses(const std::string& text, size_t dofs,
                     std::vector<std::pair<uint32_t, std::vector<double>>>* out) {
  std::istringstream frames(text);
  std::string item;
  while (std::getline(frames, item, ';')) {
    std::istringstream values(item);
    std::string frame;
    if (!(values >> frame)) return false;
    std::pair<uint32_t, std::vector<double>> pose;
    if (!ParseU32(frame, &pose.first)) return false;
    double v = 0;
    while (values >> v) {
      // Radians and metres: anything larger is not a pose.
      if (!(std::abs(v) <= 1e4) || pose.second.size() >= dofs) return false;
      pose.second.push_back(v);
    }
    if (!values.eof() || pose.second.size() != dofs) return false;
    out->push_back(std::move(pose));
  }
  return true;
}

// Where each bone's joint is (metres) with the bones' motions, as SPEC.md's
// chain composes them: a bone's rest translation plus its motion's, turned by
// its parent's world rotation; its rotation the rest's times the motion's.
std::vector<std::array<double, 3>> JointPositions(const Skeleton& skeleton,
                                                  const std::vector<BoneMotion>& motion) {
  struct Quat {
    double w, x, y, z;
  };
  const auto multiply = [](const Quat& a, const Quat& b) {
    return Quat{a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z,
                a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
                a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
                a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
  };
  const size_t n = skeleton.bones.size();
  std::vector<Quat> rotation(n);
  std::vector<std::array<double, 3>> position(n);
  for (size_t b = 0; b < n; ++b) {
    const Bone& bone = skeleton.bones[b];
    std::array<double, 3> t{};
    for (int a = 0; a < 3; ++a) {
      t[a] =
          bone.rest_translation[a] + (b < motion.size() ? motion[b].translation_um[a] * 1e-6 : 0);
    }
    const Quat rest{bone.rest_rotation[0], bone.rest_rotation[1], bone.rest_rotation[2],
                    bone.rest_rotation[3]};
    Quat dof{1, 0, 0, 0};
    if (b < motion.size()) {
      const auto& c = motion[b].rotation.c;
      const double one = double(kQ30One);
      dof = Quat{c[0] / one, c[1] / one, c[2] / one, c[3] / one};
    }
    Quat local = multiply(rest, dof);
    const double norm =
        std::sqrt(local.w * local.w + local.x * local.x + local.y * local.y + local.z * local.z);
    if (norm > 0) local = Quat{local.w / norm, local.x / norm, local.y / norm, local.z / norm};
    if (bone.parent < 0 || size_t(bone.parent) >= b) {
      position[b] = t, rotation[b] = local;
      continue;
    }
    // t turned by the parent's rotation: q t q*.
    const Quat& q = rotation[bone.parent];
    const Quat turned =
        multiply(multiply(q, Quat{0, t[0], t[1], t[2]}), Quat{q.w, -q.x, -q.y, -q.z});
    const auto& origin = position[bone.parent];
    position[b] = {origin[0] + turned.x, origin[1] + turned.y, origin[2] + turned.z};
    rotation[b] = multiply(q, local);
  }
  return position;
}

// Neighbouring parts that tracked their own frames: the poses a part tracked
// as warm-up after its range against the next part's own (decoded) poses,
// joint by joint (a twist about a limb's axis that moves no joint is not a
// disagreement).
Status CheckBorders(std::vector<Part>& parts) {
  const Skeleton& skeleton = parts[0].reader->info().model.skeleton;
  const std::vector<DofRef> dofs = skeleton.Dofs();
  for (size_t k = 0; k + 1 < parts.size(); ++k) {
    const Metadata& meta = parts[k].reader->info().metadata;
    const auto kv = std::find_if(meta.begin(), meta.end(),
                                 [](const auto& e) { return e.first == kShardPosesAfterKey; });
    if (kv == meta.end()) continue;
    std::vector<std::pair<uint32_t, std::vector<double>>> mine;
    if (!ParseShardPoses(kv->second, dofs.size(), &mine)) {
      return InvalidArgument(parts[k].path + ": malformed " + kShardPosesAfterKey);
    }
    Part& next = parts[k + 1];
    std::vector<QuantisedPose> theirs;
    FVV_RETURN_IF_ERROR(AppendPartPoses(next, &theirs));
    const MotionParams& motion = next.reader->info().motion;
    double worst = 0;
    uint32_t worst_frame = 0;
    size_t worst_bone = 0;
    for (const auto& [frame, values] : mine) {
      if (frame < next.position.first || frame - next.position.first >= theirs.size()) continue;
      const auto a = JointPositions(
          skeleton, BoneMotionsFromPose(skeleton, motion, QuantisePose(dofs, motion, values)));
      const auto b = JointPositions(
          skeleton, BoneMotionsFromPose(skeleton, motion, theirs[frame - next.position.first]));
      for (size_t j = 0; j < a.size(); ++j) {
        const double d = std::hypot(a[j][0] - b[j][0], a[j][1] - b[j][1], a[j][2] - b[j][2]);
        if (d > worst) worst = d, worst_frame = frame, worst_bone = j;
      }
    }
    if (worst > kBorderJointTolerance) {
      char amount[32];
      std::snprintf(amount, sizeof(amount), "%.1f cm", worst * 100);
      return InvalidArgument(
          parts[k].path + " and " + next.path + " disagree at their border: at frame " +
          std::to_string(worst_frame) + " of the take, the " + skeleton.bones[worst_bone].name +
          " joint is " + amount + " apart between the first's warm-up and the second's own " +
          "poses, so one of them lost the actor (docs/scale-out.md, \"Tracking in shards\"): " +
          "encode shard " + std::to_string(next.position.index) + " again with --after " +
          parts[k].path + ", which goes on from that part's poses, or track the take in one " +
          "pass and encode its shards with --poses");
    }
  }
  return Status::Ok();
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

std::string FormatShardPoses(const std::vector<uint32_t>& take_frames,
                             const std::vector<std::vector<double>>& poses) {
  std::string out;
  char number[32];
  for (size_t i = 0; i < take_frames.size() && i < poses.size(); ++i) {
    if (i > 0) out += ';';
    out += std::to_string(take_frames[i]);
    for (double v : poses[i]) {
      std::snprintf(number, sizeof(number), " %.9g", v);
      out += number;
    }
  }
  return out;
}

StatusOr<PartPoses> ReadPartPoses(const std::string& path) {
  StatusOr<Part> opened = OpenPart(path);
  if (!opened.ok()) return opened.status();
  Part& p = *opened;
  PartPoses out;
  out.position = p.position;
  const StreamInfo& info = p.reader->info();
  if (info.motion.key_interval != 1) {
    return InvalidArgument(path + ": motion key interval " +
                           std::to_string(info.motion.key_interval) + ", not 1");
  }
  std::vector<QuantisedPose> poses;
  FVV_RETURN_IF_ERROR(AppendPartPoses(p, &poses));
  const std::vector<DofRef> dofs = info.model.skeleton.Dofs();
  for (const QuantisedPose& q : poses) out.poses.push_back(DequantisePose(dofs, info.motion, q));
  return out;
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
    StatusOr<Part> p = OpenPart(path);
    if (!p.ok()) return p.status();
    parts.push_back(std::move(p).value());
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
  FVV_RETURN_IF_ERROR(CheckBorders(parts));

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
