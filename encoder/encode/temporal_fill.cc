#include "encoder/encode/temporal_fill.h"

#include <cstdlib>

namespace fvv {

TemporalFill::TemporalFill(size_t texels, uint32_t max_distance)
    : texels_(texels),
      max_distance_(max_distance),
      last_rgb_(texels * 3, 0),
      last_frame_(texels, -1) {}

uint64_t TemporalFill::Apply(uint32_t first, uint32_t frames, uint32_t cameras,
                             const std::vector<uint32_t>& texel_list,
                             const std::vector<std::vector<uint8_t>>& colour,
                             const std::vector<std::vector<int16_t>>& labels,
                             const std::vector<std::vector<int16_t>>& target, uint8_t* rgb,
                             uint8_t* mask) {
  uint64_t filled = 0;
  std::vector<uint8_t> seen(frames);
  for (uint32_t texel : texel_list) {
    for (uint32_t t = 0; t < frames; ++t) {
      seen[t] = t < labels.size() && !labels[t].empty() && labels[t][texel] >= 0;
    }
    const auto source = [&](uint32_t t) { return &colour[t][size_t(texel) * 3]; };
    for (uint32_t t = 0; t < frames; ++t) {
      if (seen[t] || t >= target.size() || target[t].empty() || target[t][texel] < 0) continue;
      // The mean of the frames within reach that saw it: this span's, and
      // the last one of the spans before.
      int sum[3] = {0, 0, 0}, count = 0;
      const auto add = [&](const uint8_t* c) {
        for (int k = 0; k < 3; ++k) sum[k] += c[k];
        ++count;
      };
      for (uint32_t u = 0; u < frames; ++u) {
        if (seen[u] && uint32_t(std::abs(int64_t(u) - int64_t(t))) <= max_distance_) add(source(u));
      }
      if (last_frame_[texel] >= 0 && first + t - last_frame_[texel] <= max_distance_) {
        add(&last_rgb_[size_t(texel) * 3]);
      }
      if (count == 0) continue;
      const size_t i = (size_t(t) * cameras + uint32_t(target[t][texel])) * texels_ + texel;
      for (int k = 0; k < 3; ++k) rgb[i * 3 + k] = uint8_t((sum[k] + count / 2) / count);
      mask[i] = 1;
      ++filled;
    }
    for (uint32_t t = frames; t-- > 0;) {
      if (!seen[t]) continue;
      for (int k = 0; k < 3; ++k) last_rgb_[size_t(texel) * 3 + k] = source(t)[k];
      last_frame_[texel] = first + t;
      break;
    }
  }
  return filled;
}

}  // namespace fvv
