#include "encoder/encode/mask_dilation.h"

#include <algorithm>
#include <cstddef>

namespace fvv {

std::vector<uint8_t> DilateMask(const uint8_t* mask, int w, int h, int r) {
  if (r < 0) {
    // Shrinking is growing the complement.
    std::vector<uint8_t> outside(size_t(w) * h);
    for (size_t i = 0; i < outside.size(); ++i) outside[i] = mask[i] == 0;
    std::vector<uint8_t> grown = DilateMask(outside.data(), w, h, -r);
    for (uint8_t& v : grown) v = !v;
    return grown;
  }
  std::vector<uint8_t> rows(size_t(w) * h), out(size_t(w) * h);
  for (int y = 0; y < h; ++y) {
    const uint8_t* in = &mask[size_t(y) * w];
    // The distance to the nearest set pixel at or before x, then after it.
    int last = -1 - r;
    for (int x = 0; x < w; ++x) {
      if (in[x]) last = x;
      rows[size_t(y) * w + x] = x - last <= r;
    }
    last = w + r;
    for (int x = w - 1; x >= 0; --x) {
      if (in[x]) last = x;
      rows[size_t(y) * w + x] |= last - x <= r;
    }
  }
  for (int x = 0; x < w; ++x) {
    int last = -1 - r;
    for (int y = 0; y < h; ++y) {
      if (rows[size_t(y) * w + x]) last = y;
      out[size_t(y) * w + x] = y - last <= r;
    }
    last = h + r;
    for (int y = h - 1; y >= 0; --y) {
      if (rows[size_t(y) * w + x]) last = y;
      out[size_t(y) * w + x] |= last - y <= r;
    }
  }
  return out;
}

}  // namespace fvv
