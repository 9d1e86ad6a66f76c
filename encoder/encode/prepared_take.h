// What ties a take's GOPs together, settled once before it is encoded in
// shards (`fvv encode --prepare DIR`, docs/scale-out.md): the body model with
// its atlas (refined where asked), and the actor's static texture that fills
// texels no camera of a frame sees, averaged over frames spread across the
// whole take. Every shard, and a whole-take encode given the same directory,
// reads it instead of building its own, so their GOPs agree.
//
// The directory: prepared.json (the take's frames, the settings the model and
// texture depend on, the poses file's checksum), model.bin (the stream's
// 'modl' box), static.png and static_coverage.png (atlas layout).
#ifndef FVV_ENCODER_ENCODE_PREPARED_TAKE_H_
#define FVV_ENCODER_ENCODE_PREPARED_TAKE_H_

#include <cstdint>
#include <string>
#include <vector>

#include "codec/base/status.h"
#include "container/body_model.h"
#include "encoder/body/generic_body.h"
#include "encoder/track/track_capture.h"

namespace fvv {

struct PreparedTake {
  uint32_t first_frame = 0, last_frame = 0;  // the take's frames in the capture
  uint32_t atlas_size = 0, gop_frames = 0;
  bool refined = false;    // the model was refined to the actor (--refine-shape)
  uint32_t poses_crc = 0;  // CRC-32C of the poses file the take was prepared with
  // No poses file: every shard tracks its own frames, with the shape here
  // fixed and `warm_up` frames tracked on each side of its range.
  bool shards_track = false;
  uint32_t warm_up = 0;
  uint32_t model_crc = 0;                // CRC-32C of model.bin
  std::vector<uint32_t> texture_frames;  // frames the static texture averages
  BodyShape shape;
  BodyModel model;                       // the stream's model: its mesh carries the atlas UVs
  std::vector<uint8_t> static_rgb;       // atlas_size^2 * 3
  std::vector<uint8_t> static_coverage;  // atlas_size^2: 1 where some frame saw the texel

  uint32_t frames() const { return last_frame - first_frame + 1; }
};

Status WritePreparedTake(const std::string& dir, const PreparedTake& take);
// Errors name the file and what is wrong with it.
StatusOr<PreparedTake> LoadPreparedTake(const std::string& dir);
// prepared.json alone: the frames and settings, without the model and texture.
StatusOr<PreparedTake> LoadPreparedTakeDescription(const std::string& dir);

// Tracking frames first..last of a take prepared to be tracked in shards, as
// every shard and a whole-take encode with it do: the prepared shape, fixed;
// the take's bounds; its warm-up.
void UsePreparedTracking(const PreparedTake& take, uint32_t first, uint32_t last,
                         TrackCaptureOptions* options);

// A shard `index` of `count` that goes on from the poses of the part before
// it (`after`, part index - 1 of the same split) instead of a first-frame
// search: its last poses become options->lead_in (as many as
// options->smoothing reads across the border, two at least).
Status GoOnAfter(const std::string& after, uint32_t index, uint32_t count,
                 TrackCaptureOptions* options);

// The frames of shard `index` of `count` of a take of `frames` frames in GOPs
// of `gop_frames`: whole time spans, as evenly shared as they divide. Offsets
// are from the take's first frame; InvalidArgument when a shard has no GOP.
struct ShardFrames {
  uint32_t first = 0, count = 0;
};
StatusOr<ShardFrames> ShardFramesOf(uint32_t frames, uint32_t gop_frames, uint32_t index,
                                    uint32_t count);

}  // namespace fvv

#endif  // FVV_ENCODER_ENCODE_PREPARED_TAKE_H_
