// Texels no camera saw in a frame, filled from time before space: a surface
// point hidden for a moment (an arm across the chest, the back turned to
// every camera for a few frames) looked in the nearest frames that saw it
// much as it looks now, closer than any average over the take (the static
// texture) or any fill from its neighbours in the atlas.
#ifndef FVV_ENCODER_ENCODE_TEMPORAL_FILL_H_
#define FVV_ENCODER_ENCODE_TEMPORAL_FILL_H_

#include <cstddef>
#include <cstdint>
#include <vector>

namespace fvv {

class TemporalFill {
 public:
  // `texels`: the atlas's size squared. A texel takes a colour from at most
  // `max_distance` frames away.
  TemporalFill(size_t texels, uint32_t max_distance);

  // One time span of `frames` frames from frame `first` (the spans come in
  // order). Per frame: `colour` (texels x 3) and `labels` (texels, >= 0 where
  // a camera saw the texel): the frame's seamless texture, each texel from
  // the camera that saw it best. Every texel of `texel_list` that no camera
  // saw in a frame, and that one saw in a frame of this span or an earlier
  // one within `max_distance`, takes the colour of the nearest such frame
  // (the earlier on a tie), written into the texture of camera
  // `target[t][texel]` (skipped where negative) in `rgb` (frames x cameras x
  // texels x 3), its `mask` (frames x cameras x texels) set to 1. Returns the
  // texels filled. Then remembers each texel's last seen colour for the
  // spans after.
  uint64_t Apply(uint32_t first, uint32_t frames, uint32_t cameras,
                 const std::vector<uint32_t>& texel_list,
                 const std::vector<std::vector<uint8_t>>& colour,
                 const std::vector<std::vector<int16_t>>& labels,
                 const std::vector<std::vector<int16_t>>& target, uint8_t* rgb, uint8_t* mask);

 private:
  size_t texels_;
  uint32_t max_distance_;
  std::vector<uint8_t> last_rgb_;
  std::vector<int64_t> last_frame_;  // -1: never seen
};

}  // namespace fvv

#endif  // FVV_ENCODER_ENCODE_TEMPORAL_FILL_H_
