// RGB <-> YUV. Two transforms: BT.601 full range in Q16 fixed point (lossy path)
// and the JPEG 2000 reversible colour transform (lossless path). Both integer-only,
// so the decoder's RGB output is bit-exact across platforms.
#ifndef FVV_CODEC_COLOUR_H_
#define FVV_CODEC_COLOUR_H_

#include <cstdint>

#include "codec/block.h"

namespace fvv {

struct Yuv {
  int32_t y, u, v;
};
struct Rgb8 {
  uint8_t r, g, b;
};

Yuv RgbToYuv(ColourSpace colour, int r, int g, int b);
Rgb8 YuvToRgb(ColourSpace colour, int32_t y, int32_t u, int32_t v);

// Interleaved RGB8 frames (one per (t, c), each h*w*3) <-> a block.
// In 4:2:0 each chroma sample is the rounded mean of its (up to) 2x2 luma sites,
// and upsampling replicates it (nearest), which keeps both sides integer and simple.
Block BlockFromRgb(const uint8_t* rgb, const Shape4D& shape, ColourSpace colour,
                   ChromaFormat chroma);
void BlockToRgb(const Block& block, uint8_t* rgb);  // rgb holds shape().count() * 3 bytes

}  // namespace fvv

#endif  // FVV_CODEC_COLOUR_H_
