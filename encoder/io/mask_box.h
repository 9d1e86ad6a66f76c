// The box around a grey mask's set pixels: what the mask operations that work
// on the person alone, not on the whole frame, and the margin that scales with
// his size read.
#ifndef FVV_ENCODER_IO_MASK_BOX_H_
#define FVV_ENCODER_IO_MASK_BOX_H_

#include <cstdint>

namespace fvv {

struct MaskBox {
  int x0 = 0, y0 = 0, x1 = -1, y1 = -1;  // inclusive; x1 < 0: no pixel is set
  bool empty() const { return x1 < 0; }
};

// `pixels`: w x h, one byte a pixel, non-zero = set.
MaskBox SetPixelBox(const uint8_t* pixels, int w, int h);

}  // namespace fvv

#endif  // FVV_ENCODER_IO_MASK_BOX_H_
