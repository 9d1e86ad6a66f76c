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

// YCbCr samples with `frac` fractional bits (block.h): 0..255 * 2^frac. RCT
// takes frac 0 only.
Yuv RgbToYuv(ColourSpace colour, int r, int g, int b, int frac = 0);
// Inline: it runs for every texel of every frame a player shows (SPEC.md 9.7).
// R = (Y 2^16 + 91881 Cr + 2^(15 + frac)) >> (16 + frac), and so on: with frac
// 0 that is Y + round_q16(91881 Cr), as format versions before 7 define it.
inline Rgb8 YuvToRgb(ColourSpace colour, int32_t y, int32_t u, int32_t v, int frac = 0) {
  auto clamp8 = [](int64_t x) { return static_cast<uint8_t>(x < 0 ? 0 : x > 255 ? 255 : x); };
  if (colour == ColourSpace::kRct) {
    const int32_t g = y - ((u + v) >> 2);
    return {clamp8(v + g), clamp8(g), clamp8(u + g)};
  }
  const int64_t cb = u - (128 << frac), cr = v - (128 << frac);
  const int64_t base = (int64_t{y} << 16) + (int64_t{1} << (15 + frac));
  const int shift = 16 + frac;
  return {clamp8((base + 91881LL * cr) >> shift),
          clamp8((base - 22554LL * cb - 46802LL * cr) >> shift),
          clamp8((base + 116130LL * cb) >> shift)};
}

// One row of BT.601 YCbCr samples with `frac` fractional bits (what the
// decoder outputs) to interleaved RGB8: exactly YuvToRgb(kYCbCr601, ..., frac)
// per texel, 16 texels at a time with AVX2 where the CPU has it.
void YcbcrRowToRgb8(const int32_t* y, const int32_t* u, const int32_t* v, uint32_t n, uint8_t* rgb,
                    int frac = 0);

// One view's 4:2:0 chroma plane (cw x ch samples, rows of cw) at luma
// resolution (w x h) by the rule of SPEC.md 9.7: nearest replicates each
// sample over its cell; bilinear weighs the sample of the texel's cell 9, its
// row and column neighbours towards the texel 3 each and the diagonal one 1, of
// 16, rounded down after adding 8, the plane's edge samples repeated outwards.
void UpsampleChroma(const int32_t* chroma, uint32_t cw, uint32_t ch, uint32_t w, uint32_t h,
                    ChromaUpsampling upsampling, int32_t* out);

// Interleaved RGB8 frames (one per (t, c), each h*w*3) <-> a block.
// In 4:2:0 each chroma sample is the rounded mean of its (up to) 2x2 luma sites,
// and the block's `upsampling` returns it to every luma site.
// With `used` (one byte per luma site, non-zero where a player shows the texel)
// the mean is over the cell's used sites where it has any: the replicated value
// that is nearest to what is shown, not pulled towards colours nobody sees.
// sample_frac: the block's fractional bits (0 for RCT).
Block BlockFromRgb(const uint8_t* rgb, const Shape4D& shape, ColourSpace colour,
                   ChromaFormat chroma, int sample_frac = 0, const UsedMask* used = nullptr,
                   ChromaUpsampling upsampling = ChromaUpsampling::kNearest);
void BlockToRgb(const Block& block, uint8_t* rgb);  // rgb holds shape().count() * 3 bytes

}  // namespace fvv

#endif  // FVV_CODEC_COLOUR_H_
