#include "encoder/capture/colour_gain.h"

#include <algorithm>
#include <cmath>

namespace fvv {

bool IsUnitGain(const std::array<double, 3>& gain) {
  return gain[0] == 1.0 && gain[1] == 1.0 && gain[2] == 1.0;
}

void ApplyColourGain(const std::array<double, 3>& gain, uint8_t* rgb, size_t pixels) {
  if (IsUnitGain(gain)) return;
  // A table per channel: 256 values each.
  std::array<std::array<uint8_t, 256>, 3> table;
  for (int k = 0; k < 3; ++k) {
    for (int v = 0; v < 256; ++v) {
      table[k][v] = uint8_t(std::clamp(std::lround(v * gain[k]), 0L, 255L));
    }
  }
  for (size_t i = 0; i < pixels; ++i) {
    for (int k = 0; k < 3; ++k) rgb[3 * i + k] = table[k][rgb[3 * i + k]];
  }
}

void ApplyColourGain(const std::array<double, 3>& gain, Image* image) {
  if (image->channels != 3) return;
  ApplyColourGain(gain, image->pixels.data(), size_t(image->width) * image->height);
}

std::array<double, 3> InverseGain(const std::array<double, 3>& gain) {
  return {1.0 / gain[0], 1.0 / gain[1], 1.0 / gain[2]};
}

}  // namespace fvv
