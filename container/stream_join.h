// Joining the shards of one take (`fvv encode --shard K/N`) into one stream:
// the parts are checked to agree (header, cameras, model, motion steps,
// metadata, consecutive GOP-aligned frames), their fragments are copied in
// order with their GOP indices and frames moved to the take's, the motion
// track's statistics are measured again over the whole take and every
// fragment's motion coded with them, and one index is written. Parts that
// tracked their own frames must agree at their borders (kShardPosesAfterKey).
// With the same
// poses and model, the result is byte for byte what one encode of the take
// writes (docs/scale-out.md).
#ifndef FVV_CONTAINER_STREAM_JOIN_H_
#define FVV_CONTAINER_STREAM_JOIN_H_

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "codec/base/status.h"
#include "container/index_box.h"

namespace fvv {

// Metadata a shard carries (SPEC.md 3.7 lets a writer add any key): which
// shard it is ("K/N", K from 0), the frames of the whole take, and where its
// first frame is in the take (a multiple of the GOP's frames).
inline constexpr char kShardKey[] = "fvv.shard";
inline constexpr char kShardTakeFramesKey[] = "fvv.take_frames";
inline constexpr char kShardFirstFrameKey[] = "fvv.shard_first_frame";
// A shard that tracked its own frames: the poses it tracked as warm-up after
// its last frame, which the next part reports as its own. The join compares
// them, so that a part whose tracking lost the actor is not joined unseen.
inline constexpr char kShardPosesAfterKey[] = "fvv.shard_poses_after";

struct ShardPosition {
  uint32_t index = 0, count = 0;        // K of N
  uint32_t take_frames = 0, first = 0;  // the take's frame count; this part's first frame in it
};

// The shard keys for `position`, to append to a part's metadata.
Metadata ShardMetadata(const ShardPosition& position);
// The position a part's metadata gives; InvalidArgument naming `what` when it
// has no shard keys or they do not parse.
StatusOr<ShardPosition> ReadShardPosition(const Metadata& metadata, const std::string& what);
// `metadata` without the shard keys.
Metadata WithoutShardKeys(const Metadata& metadata);

// The value of kShardPosesAfterKey: the take's frame numbers and their DOF
// values (radians, metres), as "FRAME V V ...;FRAME V ...".
std::string FormatShardPoses(const std::vector<uint32_t>& take_frames,
                             const std::vector<std::vector<double>>& poses);

// How far apart (metres) a joint of two neighbouring parts' poses of the same
// frame may be before the join refuses them: a limb elsewhere, not two runs'
// jitter (a few centimetres).
inline constexpr double kBorderJointTolerance = 0.10;

// A part's poses (DOF values, radians and metres), decoded from its motion
// track, and where it belongs: what a shard that follows it starts from
// (`fvv encode --shard K/N --after part_K-1.fvv`).
struct PartPoses {
  ShardPosition position;
  std::vector<std::vector<double>> poses;  // one per frame of the part
};
StatusOr<PartPoses> ReadPartPoses(const std::string& path);

struct JoinSummary {
  uint32_t parts = 0, frames = 0, fragments = 0;
  uint64_t bytes = 0;
  bool motion_recoded = false;  // false: every part already had the take's motion statistics
};

// Joins `parts` (any order) into `output` (a temporary file renamed on
// success). Errors name the part and what differs, or which part is missing.
StatusOr<JoinSummary> JoinShards(const std::vector<std::string>& parts, const std::string& output,
                                 const std::function<void(const std::string&)>& progress = {});

}  // namespace fvv

#endif  // FVV_CONTAINER_STREAM_JOIN_H_
