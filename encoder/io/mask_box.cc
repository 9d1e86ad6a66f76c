#include "encoder/io/mask_box.h"

#include <algorithm>
#include <cstddef>

namespace fvv {

MaskBox SetPixelBox(const uint8_t* pixels, int w, int h) {
  MaskBox b{w, h, -1, -1};
  for (int y = 0; y < h; ++y) {
    const uint8_t* row = pixels + size_t(y) * w;
    for (int x = 0; x < w; ++x) {
      if (!row[x]) continue;
      b.x0 = std::min(b.x0, x), b.x1 = std::max(b.x1, x);
      b.y0 = std::min(b.y0, y), b.y1 = y;
    }
  }
  return b;
}

}  // namespace fvv
