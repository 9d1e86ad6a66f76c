#include "encoder/encode/temporal_fill.h"

namespace fvv {

uint64_t FillFromNearestFrames(uint32_t frames, uint32_t cameras, size_t texels,
                               const std::vector<uint32_t>& texel_list,
                               const std::vector<std::vector<uint8_t>>& colour,
                               const std::vector<std::vector<int16_t>>& labels,
                               const std::vector<std::vector<int16_t>>& target,
                               uint32_t max_distance, uint8_t* rgb, uint8_t* mask) {
  uint64_t filled = 0;
  std::vector<uint8_t> seen(frames);
  for (uint32_t texel : texel_list) {
    for (uint32_t t = 0; t < frames; ++t) {
      seen[t] = t < labels.size() && !labels[t].empty() && labels[t][texel] >= 0;
    }
    for (uint32_t t = 0; t < frames; ++t) {
      if (seen[t] || t >= target.size() || target[t].empty() || target[t][texel] < 0) continue;
      int sum[3] = {0, 0, 0}, count = 0;
      const uint32_t from = t > max_distance ? t - max_distance : 0;
      for (uint32_t u = from; u < frames && u <= t + max_distance; ++u) {
        if (!seen[u]) continue;
        for (int k = 0; k < 3; ++k) sum[k] += colour[u][size_t(texel) * 3 + k];
        ++count;
      }
      if (count == 0) continue;
      const size_t i = (size_t(t) * cameras + uint32_t(target[t][texel])) * texels + texel;
      for (int k = 0; k < 3; ++k) rgb[i * 3 + k] = uint8_t((sum[k] + count / 2) / count);
      mask[i] = 1;
      ++filled;
    }
  }
  return filled;
}

}  // namespace fvv
