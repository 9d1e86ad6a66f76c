#include "encoder/encode/prepared_take.h"

#include <algorithm>
#include <nlohmann/json.hpp>

#include "container/box.h"
#include "container/crc32c.h"
#include "container/file_header.h"
#include "container/stream_join.h"
#include "encoder/body/body_shape_json.h"
#include "encoder/io/image_io.h"
#include "encoder/io/json_number.h"

namespace fvv {
namespace {

constexpr char kFormat[] = "fvv prepared take";
constexpr int kVersion = 1;
constexpr uint64_t kMaxJsonBytes = 1 << 20;
constexpr uint64_t kMaxModelBytes = uint64_t{256} << 20;

Status WriteText(const std::string& path, const std::string& text) {
  return WriteFileAtomic(path, reinterpret_cast<const uint8_t*>(text.data()), text.size());
}

StatusOr<Image> ReadPlane(const std::string& path, uint32_t size, int channels) {
  StatusOr<Image> img = ReadImage(path);
  if (!img.ok()) return img.status();
  if (img->width != size || img->height != size || img->channels != channels) {
    return Corrupt(path + ": not a " + std::to_string(size) + "x" + std::to_string(size) +
                   (channels == 3 ? " RGB" : " grey") + " image (the prepared atlas size)");
  }
  return img;
}

}  // namespace

Status WritePreparedTake(const std::string& dir, const PreparedTake& t) {
  FVV_RETURN_IF_ERROR(MakeDirectories(dir));
  const std::vector<uint8_t> model = WriteModelBox(t.model);
  FVV_RETURN_IF_ERROR(WriteFileAtomic(dir + "/model.bin", model.data(), model.size()));
  Image rgb;
  rgb.width = rgb.height = t.atlas_size;
  rgb.channels = 3;
  rgb.pixels = t.static_rgb;
  FVV_RETURN_IF_ERROR(WriteImage(dir + "/static.png", rgb));
  Image coverage;
  coverage.width = coverage.height = t.atlas_size;
  coverage.channels = 1;
  for (uint8_t c : t.static_coverage) coverage.pixels.push_back(c ? 255 : 0);
  FVV_RETURN_IF_ERROR(WriteImage(dir + "/static_coverage.png", coverage));
  nlohmann::json j;
  j["format"] = kFormat;
  j["version"] = kVersion;
  j["first_frame"] = t.first_frame;
  j["last_frame"] = t.last_frame;
  j["atlas_size"] = t.atlas_size;
  j["gop_frames"] = t.gop_frames;
  j["refined"] = t.refined;
  j["poses_crc32c"] = t.poses_crc;
  j["shards_track"] = t.shards_track;
  j["track_warm_up"] = t.warm_up;
  j["texture_frames"] = t.texture_frames;
  j["body_shape"] = BodyShapeToJson(t.shape);
  j["model_crc32c"] = Crc32c(model.data(), model.size());
  // Written last: a directory without it is not a prepared take.
  return WriteText(dir + "/prepared.json", j.dump(1) + "\n");
}

StatusOr<PreparedTake> LoadPreparedTakeDescription(const std::string& dir) {
  const std::string json_path = dir + "/prepared.json";
  StatusOr<std::vector<uint8_t>> text = ReadFileBytes(json_path, kMaxJsonBytes);
  if (!text.ok()) {
    return Status(text.status().code(),
                  text.status().message() + " (fvv encode --prepare " + dir + " writes it)");
  }
  const nlohmann::json j = nlohmann::json::parse(text->begin(), text->end(), nullptr, false);
  if (j.is_discarded() || !j.is_object()) return Corrupt(json_path + ": not a JSON object");
  PreparedTake t;
  try {
    if (j.at("format").get<std::string>() != kFormat) {
      return Corrupt(json_path + ": not a prepared take (format is not \"" + kFormat + "\")");
    }
    if (JsonWhole<int>(j.at("version"), "version") != kVersion) {
      return Unsupported(json_path + ": version " + j.at("version").dump() + " (this fvv reads " +
                         std::to_string(kVersion) + ")");
    }
    t.first_frame = JsonWhole<uint32_t>(j.at("first_frame"), "first_frame");
    t.last_frame = JsonWhole<uint32_t>(j.at("last_frame"), "last_frame");
    t.atlas_size = JsonWhole<uint32_t>(j.at("atlas_size"), "atlas_size");
    t.gop_frames = JsonWhole<uint32_t>(j.at("gop_frames"), "gop_frames");
    t.refined = j.at("refined").get<bool>();
    t.poses_crc = JsonWhole<uint32_t>(j.at("poses_crc32c"), "poses_crc32c");
    // Absent in takes prepared before shards could track.
    t.shards_track = j.value("shards_track", false);
    if (j.contains("track_warm_up")) {
      t.warm_up = JsonWhole<uint32_t>(j.at("track_warm_up"), "track_warm_up");
    }
    const nlohmann::json& frames = j.at("texture_frames");
    if (!frames.is_array() || frames.size() > 65536) {
      return Corrupt(json_path + ": texture_frames is not a list of frames");
    }
    for (const nlohmann::json& f : frames) {
      t.texture_frames.push_back(JsonWhole<uint32_t>(f, "texture_frames"));
    }
    t.model_crc = JsonWhole<uint32_t>(j.at("model_crc32c"), "model_crc32c");
    StatusOr<BodyShape> shape = BodyShapeFromJson(j.at("body_shape"), json_path);
    if (!shape.ok()) return shape.status();
    t.shape = *shape;
  } catch (const std::exception& e) {  // nlohmann's, or JsonWhole's range
    return Corrupt(json_path + ": " + e.what());
  }
  if (t.last_frame < t.first_frame || t.atlas_size < 16 || t.atlas_size > 4096 ||
      t.gop_frames == 0 || t.gop_frames > 65535 || t.warm_up > 100000) {
    return Corrupt(json_path + ": frames, atlas size, GOP frames or warm-up out of range");
  }
  return t;
}

StatusOr<PreparedTake> LoadPreparedTake(const std::string& dir) {
  StatusOr<PreparedTake> described = LoadPreparedTakeDescription(dir);
  if (!described.ok()) return described.status();
  PreparedTake t = std::move(*described);
  const std::string model_path = dir + "/model.bin";
  StatusOr<std::vector<uint8_t>> model = ReadFileBytes(model_path, kMaxModelBytes);
  if (!model.ok()) return model.status();
  if (Crc32c(model->data(), model->size()) != t.model_crc) {
    return Corrupt(model_path + ": its checksum is not the one prepared.json gives");
  }
  StatusOr<BoxHeader> box = ParseBoxHeader(model->data(), model->size(), 0, "model.bin");
  if (!box.ok()) return Corrupt(model_path + ": " + box.status().message());
  if (box->type != box::kModel || box->size != model->size()) {
    return Corrupt(model_path + ": not one 'modl' box");
  }
  const Status read =
      ReadModel(*box, model->data() + box->header_size, AllLevels().back(), &t.model);
  if (!read.ok()) return Status(read.code(), model_path + ": " + read.message());
  StatusOr<Image> rgb = ReadPlane(dir + "/static.png", t.atlas_size, 3);
  if (!rgb.ok()) return rgb.status();
  StatusOr<Image> coverage = ReadPlane(dir + "/static_coverage.png", t.atlas_size, 1);
  if (!coverage.ok()) return coverage.status();
  t.static_rgb = std::move(rgb->pixels);
  for (uint8_t c : coverage->pixels) t.static_coverage.push_back(c >= 128);
  return t;
}

void UsePreparedTracking(const PreparedTake& take, uint32_t first, uint32_t last,
                         TrackCaptureOptions* o) {
  o->first = first;
  o->last = last;
  o->take_first = take.first_frame;
  o->take_last = take.last_frame;
  o->warm_up = take.warm_up;
  o->tracker.fixed_shape = take.shape;
}

Status GoOnAfter(const std::string& after, uint32_t index, uint32_t count, TrackCaptureOptions* o) {
  if (index == 0) return InvalidArgument("--after: shard 0 has no part before it");
  FVV_ASSIGN_OR_RETURN(const PartPoses before, ReadPartPoses(after));
  if (before.position.count != count || before.position.index + 1 != index) {
    return InvalidArgument(
        "--after " + after + " is part " + std::to_string(before.position.index) + " of " +
        std::to_string(before.position.count) + ", not part " + std::to_string(index - 1) + " of " +
        std::to_string(count) + " (the part just before shard " + std::to_string(index) + ")");
  }
  if (before.poses.size() < 2) return InvalidArgument("--after " + after + ": under 2 frames");
  const size_t keep = std::min(before.poses.size(), size_t(std::max(2, o->smoothing.Radius())));
  o->lead_in.assign(before.poses.end() - keep, before.poses.end());
  return Status::Ok();
}

StatusOr<ShardFrames> ShardFramesOf(uint32_t frames, uint32_t gop_frames, uint32_t index,
                                    uint32_t count) {
  if (count == 0 || index >= count) {
    return InvalidArgument("shard " + std::to_string(index) + "/" + std::to_string(count) +
                           ": K must be below N");
  }
  const uint64_t spans = (uint64_t{frames} + gop_frames - 1) / gop_frames;
  const uint64_t begin = spans * index / count, end = spans * (index + 1) / count;
  if (begin == end) {
    return InvalidArgument("shard " + std::to_string(index) + "/" + std::to_string(count) +
                           " has no GOP: the take has " + std::to_string(spans) +
                           " time spans of " + std::to_string(gop_frames) +
                           " frames (use at most that many shards)");
  }
  ShardFrames s;
  s.first = uint32_t(begin * gop_frames);
  s.count = uint32_t(std::min<uint64_t>(frames, end * gop_frames) - s.first);
  return s;
}

}  // namespace fvv
