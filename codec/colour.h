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
// Inline: it runs for every texel of every frame a player shows (SPEC.md 9.7).
inline Rgb8 YuvToRgb(ColourSpace colour, int32_t y, int32_t u, int32_t v) {
  auto clamp8 = [](int32_t x) { return static_cast<uint8_t>(x < 0 ? 0 : x > 255 ? 255 : x); };
  auto round_q16 = [](int64_t a) { return static_cast<int32_t>((a + 32768) >> 16); };
  if (colour == ColourSpace::kRct) {
    const int32_t g = y - ((u + v) >> 2);
    return {clamp8(v + g), clamp8(g), clamp8(u + g)};
  }
  const int64_t cb = u - 128, cr = v - 128;
  return {clamp8(y + round_q16(91881LL * cr)), clamp8(y + round_q16(-22554LL * cb - 46802LL * cr)),
          clamp8(y + round_q16(116130LL * cb))};
}

// One row of BT.601 YCbCr samples, each in 0..255 (what the decoder outputs), to
// interleaved RGB8: exactly YuvToRgb(kYCbCr601, ...) per texel, 16 texels at a
// time with AVX2 where the CPU has it.
void YcbcrRowToRgb8(const int32_t* y, const int32_t* u, const int32_t* v, uint32_t n, uint8_t* rgb);

// Interleaved RGB8 frames (one per (t, c), each h*w*3) <-> a block.
// In 4:2:0 each chroma sample is the rounded mean of its (up to) 2x2 luma sites,
// and upsampling replicates it (nearest), which keeps both sides integer and simple.
Block BlockFromRgb(const uint8_t* rgb, const Shape4D& shape, ColourSpace colour,
                   ChromaFormat chroma);
void BlockToRgb(const Block& block, uint8_t* rgb);  // rgb holds shape().count() * 3 bytes

}  // namespace fvv

#endif  // FVV_CODEC_COLOUR_H_
