// Texels no camera saw in a frame, filled from time before space: a surface
// point hidden for a moment (an arm across the chest, the back turned to
// every camera for a few frames) looked in the nearest frames that saw it
// much as it looks now, closer than an average over the whole take (the
// static texture) or any fill from its neighbours in the atlas. The fill
// reads the frames of one time span only, so a take encoded in shards (which
// split at spans) gets the same textures as encoded whole.
#ifndef FVV_ENCODER_ENCODE_TEMPORAL_FILL_H_
#define FVV_ENCODER_ENCODE_TEMPORAL_FILL_H_

#include <cstddef>
#include <cstdint>
#include <vector>

namespace fvv {

// One time span of `frames` frames, `cameras` textures of `texels` texels
// each. Per frame: `colour` (texels x 3) and `labels` (texels, >= 0 where a
// camera saw the texel): the frame's seamless texture, each texel from the
// camera that saw it best. Every texel of `texel_list` that no camera saw in
// a frame takes the mean colour of the span's frames within `max_distance`
// that saw it, written into the texture of camera `target[t][texel]`
// (skipped where negative) in `rgb` (frames x cameras x texels x 3), its
// `mask` (frames x cameras x texels) set to 1. Returns the texels filled.
uint64_t FillFromNearestFrames(uint32_t frames, uint32_t cameras, size_t texels,
                               const std::vector<uint32_t>& texel_list,
                               const std::vector<std::vector<uint8_t>>& colour,
                               const std::vector<std::vector<int16_t>>& labels,
                               const std::vector<std::vector<int16_t>>& target,
                               uint32_t max_distance, uint8_t* rgb, uint8_t* mask);

}  // namespace fvv

#endif  // FVV_ENCODER_ENCODE_TEMPORAL_FILL_H_
