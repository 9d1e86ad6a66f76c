// The encoder's side of surface_displacement.h.
#include "container/surface_displacement.h"
#include "container/zstd_frame.h"

namespace fvv {

std::vector<uint8_t> EncodeSurfaceDisplacements(const std::vector<int32_t>& values, uint32_t frames,
                                                uint32_t vertices) {
  std::vector<uint8_t> bytes;
  bytes.reserve(values.size() + values.size() / 4);
  for (uint32_t t = 0; t < frames; ++t) {
    for (uint32_t v = 0; v < vertices; ++v) {
      const int64_t residual =
          values[size_t(t) * vertices + v] - PredictSurfaceValue(values.data(), vertices, t, v);
      // Zigzag: 0, -1, 1, -2, ... -> 0, 1, 2, 3, ... (shifted as unsigned).
      uint64_t r =
          ((static_cast<uint64_t>(residual) << 1) ^ static_cast<uint64_t>(residual >> 63)) &
          0xFFFFFFFFu;
      while (r >= 0x80) {
        bytes.push_back(static_cast<uint8_t>(r | 0x80));
        r >>= 7;
      }
      bytes.push_back(static_cast<uint8_t>(r));
    }
  }
  return ZstdCompress(bytes.data(), bytes.size(), 19);
}

}  // namespace fvv
