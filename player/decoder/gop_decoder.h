// Decoding of one GOP time span: the motion of its frames and the textures and
// masks of every camera group, under a byte or time budget.
#ifndef FVV_PLAYER_DECODER_GOP_DECODER_H_
#define FVV_PLAYER_DECODER_GOP_DECODER_H_

#include <memory>
#include <vector>

#include "codec/base/parallel.h"
#include "codec/base/sample_pool.h"
#include "codec/block.h"
#include "container/fragment.h"
#include "container/motion_track.h"
#include "container/stream_info.h"

namespace fvv {

struct GopBudget {
  uint64_t max_bytes = 0;  // texture bytes per fragment; 0 = all
  double max_ms = 0;       // for the whole span; 0 = no limit
  uint64_t cameras = 0;    // bit c: decode camera c's group; 0 = every camera
  double floor_share = 0;  // of each stream, decoded even past max_ms

  // A GOP decoded under `this` is at least as good as one decoded under `other`
  // (and holds every camera `other` asks for).
  bool Covers(const GopBudget& other) const;
  // Whether the group of cameras [first, first + count) is decoded.
  bool WantsGroup(uint32_t first, uint32_t count) const;
};

struct DecodedGop {
  DecodedGop() = default;
  DecodedGop(const DecodedGop&) = default;
  DecodedGop& operator=(const DecodedGop&) = default;
  // Hands the texture buffers back to the pool they came from, if any.
  ~DecodedGop();

  uint32_t span = 0;
  uint32_t first_frame = 0, frame_count = 0;
  GopBudget budget;
  std::vector<DecodedFrame> motion;         // frame_count entries
  std::vector<FragmentInfo> groups;         // one per camera group
  std::vector<bool> decoded;                // per camera group: false when the budget left it out
  std::vector<Block> textures;              // decoded YUV, per camera group
  std::vector<std::vector<uint8_t>> masks;  // per camera group; empty without masks
  // The surface of each frame (SPEC.md 3.5.2): its bind-pose positions,
  // vertex_count x 3 floats; empty when the stream carries none for the GOP
  // or the budget's prefix ends before its last chunk (the model's surface).
  std::vector<std::vector<float>> surface;
  uint64_t bytes_decoded = 0, bytes_available = 0;
  std::array<int, 3> bitplanes{};  // fewest complete bitplanes over the groups
  double ms = 0;
  bool complete = true;
  std::shared_ptr<SamplePool> sample_pool;  // where `textures` go when the GOP is dropped
};

// `fragments` are the span's fragments, camera group 0 first; `threads` is how
// many tasks `runner` runs at once; `sample_pool` (optional) supplies the
// textures' buffers and takes them back when the GOP is dropped.
StatusOr<std::shared_ptr<DecodedGop>> DecodeGop(const StreamInfo& info,
                                                const std::vector<FragmentData>& fragments,
                                                const GopBudget& budget,
                                                const ParallelRunner& runner, unsigned threads = 1,
                                                std::shared_ptr<SamplePool> sample_pool = nullptr);

}  // namespace fvv

#endif  // FVV_PLAYER_DECODER_GOP_DECODER_H_
