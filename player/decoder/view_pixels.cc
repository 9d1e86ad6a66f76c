#include "player/decoder/view_pixels.h"

#include <vector>

#include "codec/colour.h"

namespace fvv {

void ViewPixels(const Block& block, uint32_t t, uint32_t c, ViewFormat format,
                std::unique_ptr<uint8_t[]>* pixels) {
  const Shape4D& luma = block.shape();
  const Shape4D& chroma = block.channels[1].shape;
  const uint32_t w = luma.width(), h = luma.height();
  const bool half = block.chroma == ChromaFormat::k420;
  pixels->reset(new uint8_t[size_t{w} * h * 3]);
  uint8_t* out = pixels->get();
  const int32_t* Y = block.channels[0].samples.data() + luma.Index(t, c, 0, 0);
  const int32_t* U = block.channels[1].samples.data() + chroma.Index(t, c, 0, 0);
  const int32_t* V = block.channels[2].samples.data() + chroma.Index(t, c, 0, 0);
  const int frac = block.sample_frac;
  // 4:2:0 chroma at luma resolution first, by the stream's rule (SPEC.md 9.7).
  std::vector<int32_t> u_full, v_full;
  if (half) {
    u_full.resize(size_t{w} * h);
    v_full.resize(size_t{w} * h);
    UpsampleChroma(U, chroma.width(), chroma.height(), w, h, block.upsampling, u_full.data());
    UpsampleChroma(V, chroma.width(), chroma.height(), w, h, block.upsampling, v_full.data());
    U = u_full.data();
    V = v_full.data();
  }
  if (format == ViewFormat::kRgb8 && block.colour == ColourSpace::kYCbCr601) {
    for (uint32_t y = 0; y < h; ++y) {
      const size_t row = size_t{y} * w;
      YcbcrRowToRgb8(Y + row, U + row, V + row, w, out + 3 * row, frac);
    }
    return;
  }
  // YUV444 bytes: samples with fractional bits rounded to whole ones.
  const int32_t round = frac ? 1 << (frac - 1) : 0;
  auto to_byte = [frac, round](int32_t s) { return static_cast<uint8_t>((s + round) >> frac); };
  for (uint32_t y = 0; y < h; ++y) {
    for (uint32_t x = 0; x < w; ++x) {
      const size_t i = size_t{y} * w + x;
      if (format == ViewFormat::kRgb8) {
        const Rgb8 p = YuvToRgb(block.colour, Y[i], U[i], V[i], frac);
        out[3 * i] = p.r;
        out[3 * i + 1] = p.g;
        out[3 * i + 2] = p.b;
      } else {
        out[i] = to_byte(Y[i]);
        out[size_t{w} * h + i] = to_byte(U[i]);
        out[2 * size_t{w} * h + i] = to_byte(V[i]);
      }
    }
  }
}

}  // namespace fvv
