#include "codec/colour.h"

#include <algorithm>

namespace fvv {
namespace {

int32_t Clamp(int32_t v, int32_t lo, int32_t hi) { return std::min(std::max(v, lo), hi); }

// Rounded (a * 2^-16) for signed a: floor(a / 65536 + 1/2).
int32_t RoundQ16(int64_t a) { return static_cast<int32_t>((a + 32768) >> 16); }

}  // namespace

Yuv RgbToYuv(ColourSpace colour, int r, int g, int b) {
  if (colour == ColourSpace::kRct) {
    // floor((R + 2G + B) / 4), B - G, R - G (ITU-T T.800 Annex G.2).
    return {(r + 2 * g + b) >> 2, b - g, r - g};
  }
  // BT.601 full range; coefficients round(c * 65536).
  int32_t y = RoundQ16(19595LL * r + 38470LL * g + 7471LL * b);
  int32_t u = RoundQ16(-11059LL * r - 21709LL * g + 32768LL * b) + 128;
  int32_t v = RoundQ16(32768LL * r - 27439LL * g - 5329LL * b) + 128;
  return {Clamp(y, 0, 255), Clamp(u, 0, 255), Clamp(v, 0, 255)};
}

Block BlockFromRgb(const uint8_t* rgb, const Shape4D& shape, ColourSpace colour,
                   ChromaFormat chroma) {
  Block block;
  block.colour = colour;
  block.chroma = chroma;
  block.channels[0] = Plane4D(shape);
  const Shape4D cshape = ChromaShape(shape, chroma);
  block.channels[1] = Plane4D(cshape);
  block.channels[2] = Plane4D(cshape);
  const size_t n = shape.count();
  std::vector<int32_t> u_full, v_full;
  if (chroma == ChromaFormat::k420) {
    u_full.resize(n);
    v_full.resize(n);
  }
  for (size_t i = 0; i < n; ++i) {
    const Yuv p = RgbToYuv(colour, rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2]);
    block.channels[0].samples[i] = p.y;
    if (chroma == ChromaFormat::k444) {
      block.channels[1].samples[i] = p.u;
      block.channels[2].samples[i] = p.v;
    } else {
      u_full[i] = p.u;
      v_full[i] = p.v;
    }
  }
  if (chroma == ChromaFormat::k420) {
    const uint32_t h = shape.height(), w = shape.width();
    for (uint32_t tc = 0; tc < shape.frames() * shape.cameras(); ++tc) {
      for (uint32_t cy = 0; cy < cshape.height(); ++cy) {
        for (uint32_t cx = 0; cx < cshape.width(); ++cx) {
          int32_t su = 0, sv = 0, k = 0;
          for (uint32_t y = 2 * cy; y < std::min(h, 2 * cy + 2); ++y) {
            for (uint32_t x = 2 * cx; x < std::min(w, 2 * cx + 2); ++x) {
              const size_t i = (size_t{tc} * h + y) * w + x;
              su += u_full[i];
              sv += v_full[i];
              ++k;
            }
          }
          const size_t o = (size_t{tc} * cshape.height() + cy) * cshape.width() + cx;
          // Round half away from zero so negative RCT chroma is treated symmetrically.
          auto avg = [k](int32_t s) { return s >= 0 ? (s + k / 2) / k : -((-s + k / 2) / k); };
          block.channels[1].samples[o] = avg(su);
          block.channels[2].samples[o] = avg(sv);
        }
      }
    }
  }
  return block;
}

void BlockToRgb(const Block& block, uint8_t* rgb) {
  const Shape4D& shape = block.shape();
  const Shape4D& cshape = block.channels[1].shape;
  const bool sub = block.chroma == ChromaFormat::k420;
  const uint32_t h = shape.height(), w = shape.width();
  for (uint32_t tc = 0; tc < shape.frames() * shape.cameras(); ++tc) {
    for (uint32_t y = 0; y < h; ++y) {
      for (uint32_t x = 0; x < w; ++x) {
        const size_t i = (size_t{tc} * h + y) * w + x;
        const size_t ci = sub ? (size_t{tc} * cshape.height() + y / 2) * cshape.width() + x / 2 : i;
        const Rgb8 p = YuvToRgb(block.colour, block.channels[0].samples[i],
                                block.channels[1].samples[ci], block.channels[2].samples[ci]);
        rgb[3 * i] = p.r;
        rgb[3 * i + 1] = p.g;
        rgb[3 * i + 2] = p.b;
      }
    }
  }
}

}  // namespace fvv
