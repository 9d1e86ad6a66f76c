#include "codec/colour.h"

#include <algorithm>
#include <vector>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define FVV_COLOUR_AVX2 1
#endif
#if defined(__wasm_simd128__)
#include <wasm_simd128.h>
#define FVV_COLOUR_WASM_SIMD 1
#endif

namespace fvv {
namespace {

int32_t Clamp(int32_t v, int32_t lo, int32_t hi) { return std::min(std::max(v, lo), hi); }

// Rounded (a * 2^-(16 - frac)) for signed a: floor(a / 2^(16 - frac) + 1/2).
int32_t RoundQ16(int64_t a, int frac) {
  return static_cast<int32_t>((a + (int64_t{1} << (15 - frac))) >> (16 - frac));
}

#if defined(FVV_COLOUR_AVX2) || defined(FVV_COLOUR_WASM_SIMD)
// Byte shuffle masks that put channel k of 16 texels at its places in output bytes
// [16 j, 16 j + 16) of 48 interleaved ones (0x80: leave zero).
struct InterleaveMasks {
  alignas(16) uint8_t m[3][3][16];  // [output block j][channel k]
  constexpr InterleaveMasks() : m{} {
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k)
        for (int i = 0; i < 16; ++i) {
          const int byte = 16 * j + i;
          m[j][k][i] = byte % 3 == k ? static_cast<uint8_t>(byte / 3) : 0x80;
        }
  }
};
constexpr InterleaveMasks kInterleave;
#endif

#ifdef FVV_COLOUR_AVX2

// 16 int32 lanes (two vectors) clamped to 0..255 by saturating packs, in order.
__attribute__((target("avx2"))) inline __m128i PackToBytes(__m256i lo, __m256i hi) {
  const __m256i words = _mm256_permute4x64_epi64(_mm256_packs_epi32(lo, hi), 0xD8);
  const __m256i bytes = _mm256_packus_epi16(words, words);
  return _mm256_castsi256_si128(_mm256_permute4x64_epi64(bytes, 0x08));
}

// In 32-bit lanes: with frac <= kMaxSampleFrac, Y 2^16 < 2^28 and every
// product below is under 2^28 in magnitude, so no sum overflows.
__attribute__((target("avx2"))) uint32_t YcbcrRowToRgb8Avx2(const int32_t* y, const int32_t* u,
                                                            const int32_t* v, uint32_t n,
                                                            uint8_t* out, int frac) {
  const __m256i k128 = _mm256_set1_epi32(128 << frac), half = _mm256_set1_epi32(1 << (15 + frac));
  const __m128i shift = _mm_cvtsi32_si128(16 + frac);
  const __m256i kr = _mm256_set1_epi32(91881), kgb = _mm256_set1_epi32(-22554),
                kgr = _mm256_set1_epi32(-46802), kb = _mm256_set1_epi32(116130);
  uint32_t i = 0;
  for (; i + 16 <= n; i += 16) {
    __m256i r[2], g[2], b[2];
    for (int h = 0; h < 2; ++h) {
      const __m256i Y = _mm256_add_epi32(
          _mm256_slli_epi32(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(y + i + 8 * h)),
                            16),
          half);
      const __m256i cb = _mm256_sub_epi32(
          _mm256_loadu_si256(reinterpret_cast<const __m256i*>(u + i + 8 * h)), k128);
      const __m256i cr = _mm256_sub_epi32(
          _mm256_loadu_si256(reinterpret_cast<const __m256i*>(v + i + 8 * h)), k128);
      r[h] = _mm256_sra_epi32(_mm256_add_epi32(Y, _mm256_mullo_epi32(kr, cr)), shift);
      g[h] = _mm256_sra_epi32(_mm256_add_epi32(Y, _mm256_add_epi32(_mm256_mullo_epi32(kgb, cb),
                                                                   _mm256_mullo_epi32(kgr, cr))),
                              shift);
      b[h] = _mm256_sra_epi32(_mm256_add_epi32(Y, _mm256_mullo_epi32(kb, cb)), shift);
    }
    const __m128i planes[3] = {PackToBytes(r[0], r[1]), PackToBytes(g[0], g[1]),
                               PackToBytes(b[0], b[1])};
    for (int j = 0; j < 3; ++j) {
      __m128i block = _mm_setzero_si128();
      for (int k = 0; k < 3; ++k)
        block = _mm_or_si128(
            block,
            _mm_shuffle_epi8(
                planes[k], _mm_load_si128(reinterpret_cast<const __m128i*>(kInterleave.m[j][k]))));
      _mm_storeu_si128(reinterpret_cast<__m128i*>(out + 3 * i + 16 * j), block);
    }
  }
  return i;
}
#endif

#ifdef FVV_COLOUR_WASM_SIMD
// The AVX2 path's arithmetic, 4 lanes at a time, in WebAssembly SIMD (the web
// player converts every texel of every frame it shows).
uint32_t YcbcrRowToRgb8WasmSimd(const int32_t* y, const int32_t* u, const int32_t* v, uint32_t n,
                                uint8_t* out, int frac) {
  const v128_t k128 = wasm_i32x4_splat(128 << frac), half = wasm_i32x4_splat(1 << (15 + frac));
  const uint32_t shift = 16 + uint32_t(frac);
  const v128_t kr = wasm_i32x4_splat(91881), kgb = wasm_i32x4_splat(-22554),
               kgr = wasm_i32x4_splat(-46802), kb = wasm_i32x4_splat(116130);
  uint32_t i = 0;
  for (; i + 16 <= n; i += 16) {
    v128_t r[4], g[4], b[4];
    for (int q = 0; q < 4; ++q) {
      const v128_t Y = wasm_i32x4_add(wasm_i32x4_shl(wasm_v128_load(y + i + 4 * q), 16), half);
      const v128_t cb = wasm_i32x4_sub(wasm_v128_load(u + i + 4 * q), k128);
      const v128_t cr = wasm_i32x4_sub(wasm_v128_load(v + i + 4 * q), k128);
      r[q] = wasm_i32x4_shr(wasm_i32x4_add(Y, wasm_i32x4_mul(kr, cr)), shift);
      g[q] = wasm_i32x4_shr(
          wasm_i32x4_add(Y, wasm_i32x4_add(wasm_i32x4_mul(kgb, cb), wasm_i32x4_mul(kgr, cr))),
          shift);
      b[q] = wasm_i32x4_shr(wasm_i32x4_add(Y, wasm_i32x4_mul(kb, cb)), shift);
    }
    // Saturating narrows clamp to 0..255 as clamp8 does.
    auto bytes = [](const v128_t* c) {
      return wasm_u8x16_narrow_i16x8(wasm_i16x8_narrow_i32x4(c[0], c[1]),
                                     wasm_i16x8_narrow_i32x4(c[2], c[3]));
    };
    const v128_t planes[3] = {bytes(r), bytes(g), bytes(b)};
    for (int j = 0; j < 3; ++j) {
      // Swizzle indices past 15 (the masks' 0x80) give zero bytes.
      v128_t block = wasm_i64x2_splat(0);
      for (int k = 0; k < 3; ++k) {
        block =
            wasm_v128_or(block, wasm_i8x16_swizzle(planes[k], wasm_v128_load(kInterleave.m[j][k])));
      }
      wasm_v128_store(out + 3 * i + 16 * j, block);
    }
  }
  return i;
}
#endif

}  // namespace

void YcbcrRowToRgb8(const int32_t* y, const int32_t* u, const int32_t* v, uint32_t n, uint8_t* rgb,
                    int frac) {
  uint32_t i = 0;
#ifdef FVV_COLOUR_AVX2
  static const bool avx2 = __builtin_cpu_supports("avx2");
  if (avx2) i = YcbcrRowToRgb8Avx2(y, u, v, n, rgb, frac);
#endif
#ifdef FVV_COLOUR_WASM_SIMD
  i = YcbcrRowToRgb8WasmSimd(y, u, v, n, rgb, frac);
#endif
  for (; i < n; ++i) {
    const Rgb8 p = YuvToRgb(ColourSpace::kYCbCr601, y[i], u[i], v[i], frac);
    rgb[3 * i] = p.r;
    rgb[3 * i + 1] = p.g;
    rgb[3 * i + 2] = p.b;
  }
}

Yuv RgbToYuv(ColourSpace colour, int r, int g, int b, int frac) {
  if (colour == ColourSpace::kRct) {
    // floor((R + 2G + B) / 4), B - G, R - G (ITU-T T.800 Annex G.2).
    return {(r + 2 * g + b) >> 2, b - g, r - g};
  }
  // BT.601 full range; coefficients round(c * 65536).
  const int32_t top = 255 << frac, mid = 128 << frac;
  int32_t y = RoundQ16(19595LL * r + 38470LL * g + 7471LL * b, frac);
  int32_t u = RoundQ16(-11059LL * r - 21709LL * g + 32768LL * b, frac) + mid;
  int32_t v = RoundQ16(32768LL * r - 27439LL * g - 5329LL * b, frac) + mid;
  return {Clamp(y, 0, top), Clamp(u, 0, top), Clamp(v, 0, top)};
}

namespace {

// The rounded mean of a sum of k values, half away from zero (RCT chroma is signed).
int32_t RoundedMean(int64_t s, int64_t k) {
  return int32_t(s >= 0 ? (s + k / 2) / k : -((-s + k / 2) / k));
}

// The box mean is the best sample for replication, not for bilinear
// interpolation, which mixes in the neighbours. One correction step moves each
// sample by its cell's mean error after interpolation (over the cell's used
// texels where it has any): +0.2 to +1.1 dB RGB at 280:1 to 20:1 on the demo
// atlas textures (docs/encoder.md); more steps gained nothing more.
void MatchChromaToBilinear(const std::vector<int32_t>& full, const UsedMask* used, Block* block,
                           int channel) {
  const Shape4D& shape = block->shape();
  const Shape4D& cshape = block->channels[channel].shape;
  const uint32_t w = shape.width(), h = shape.height(), cw = cshape.width(), ch = cshape.height();
  const SampleRange range = ChannelRange(block->colour, channel, block->sample_frac);
  std::vector<int32_t> up(size_t{w} * h);
  for (uint32_t tc = 0; tc < shape.frames() * shape.cameras(); ++tc) {
    int32_t* c = block->channels[channel].samples.data() + size_t{tc} * cw * ch;
    const int32_t* target = full.data() + size_t{tc} * w * h;
    const uint8_t* seen = used ? used->data() + size_t{tc} * w * h : nullptr;
    UpsampleChroma(c, cw, ch, w, h, ChromaUpsampling::kBilinear, up.data());
    for (uint32_t cy = 0; cy < ch; ++cy) {
      for (uint32_t cx = 0; cx < cw; ++cx) {
        int64_t error = 0, k = 0;
        // As the mean: the used sites, or all of them when none is used.
        for (int pass = seen ? 0 : 1; pass < 2 && k == 0; ++pass) {
          for (uint32_t y = 2 * cy; y < std::min(h, 2 * cy + 2); ++y) {
            for (uint32_t x = 2 * cx; x < std::min(w, 2 * cx + 2); ++x) {
              const size_t i = size_t{y} * w + x;
              if (pass == 0 && !seen[i]) continue;
              error += target[i] - up[i];
              ++k;
            }
          }
        }
        int32_t& sample = c[size_t{cy} * cw + cx];
        sample = std::clamp(sample + RoundedMean(error, k), range.min, range.max);
      }
    }
  }
}

}  // namespace

Block BlockFromRgb(const uint8_t* rgb, const Shape4D& shape, ColourSpace colour,
                   ChromaFormat chroma, int sample_frac, const UsedMask* used,
                   ChromaUpsampling upsampling) {
  Block block;
  block.colour = colour;
  block.upsampling = upsampling;
  block.chroma = chroma;
  block.sample_frac = static_cast<uint8_t>(colour == ColourSpace::kRct ? 0 : sample_frac);
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
    const Yuv p = RgbToYuv(colour, rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2], block.sample_frac);
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
    const bool weighted = used && used->size() == n;
    const uint32_t h = shape.height(), w = shape.width();
    for (uint32_t tc = 0; tc < shape.frames() * shape.cameras(); ++tc) {
      for (uint32_t cy = 0; cy < cshape.height(); ++cy) {
        for (uint32_t cx = 0; cx < cshape.width(); ++cx) {
          int32_t su = 0, sv = 0, k = 0;
          // Pass 0 takes the used sites; pass 1 all of them, when none is used.
          for (int pass = weighted ? 0 : 1; pass < 2 && k == 0; ++pass) {
            for (uint32_t y = 2 * cy; y < std::min(h, 2 * cy + 2); ++y) {
              for (uint32_t x = 2 * cx; x < std::min(w, 2 * cx + 2); ++x) {
                const size_t i = (size_t{tc} * h + y) * w + x;
                if (pass == 0 && !(*used)[i]) continue;
                su += u_full[i];
                sv += v_full[i];
                ++k;
              }
            }
          }
          const size_t o = (size_t{tc} * cshape.height() + cy) * cshape.width() + cx;
          block.channels[1].samples[o] = RoundedMean(su, k);
          block.channels[2].samples[o] = RoundedMean(sv, k);
        }
      }
    }
    if (upsampling == ChromaUpsampling::kBilinear) {
      MatchChromaToBilinear(u_full, weighted ? used : nullptr, &block, 1);
      MatchChromaToBilinear(v_full, weighted ? used : nullptr, &block, 2);
    }
  }
  return block;
}

void UpsampleChroma(const int32_t* chroma, uint32_t cw, uint32_t ch, uint32_t w, uint32_t h,
                    ChromaUpsampling upsampling, int32_t* out) {
  for (uint32_t y = 0; y < h; ++y) {
    const uint32_t cy = y >> 1;
    const int32_t* row = chroma + size_t{cy} * cw;
    int32_t* o = out + size_t{y} * w;
    if (upsampling == ChromaUpsampling::kNearest) {
      for (uint32_t x = 0; x < w; ++x) o[x] = row[x >> 1];
      continue;
    }
    // The neighbour row towards the texel: below for odd rows, above for even.
    const uint32_t ny = (y & 1) ? std::min(cy + 1, ch - 1) : (cy == 0 ? 0 : cy - 1);
    const int32_t* near = chroma + size_t{ny} * cw;
    for (uint32_t x = 0; x < w; ++x) {
      const uint32_t cx = x >> 1;
      const uint32_t nx = (x & 1) ? std::min(cx + 1, cw - 1) : (cx == 0 ? 0 : cx - 1);
      o[x] = (9 * row[cx] + 3 * near[cx] + 3 * row[nx] + near[nx] + 8) >> 4;
    }
  }
}

void BlockToRgb(const Block& block, uint8_t* rgb) {
  const Shape4D& shape = block.shape();
  const Shape4D& cshape = block.channels[1].shape;
  const bool sub = block.chroma == ChromaFormat::k420;
  const uint32_t h = shape.height(), w = shape.width();
  const size_t view = size_t{w} * h, cview = size_t{cshape.width()} * cshape.height();
  std::vector<int32_t> u_full, v_full;
  if (sub) {
    u_full.resize(view);
    v_full.resize(view);
  }
  for (uint32_t tc = 0; tc < shape.frames() * shape.cameras(); ++tc) {
    const int32_t* y_plane = block.channels[0].samples.data() + tc * view;
    const int32_t* u_plane = block.channels[1].samples.data() + tc * (sub ? cview : view);
    const int32_t* v_plane = block.channels[2].samples.data() + tc * (sub ? cview : view);
    if (sub) {
      UpsampleChroma(u_plane, cshape.width(), cshape.height(), w, h, block.upsampling,
                     u_full.data());
      UpsampleChroma(v_plane, cshape.width(), cshape.height(), w, h, block.upsampling,
                     v_full.data());
      u_plane = u_full.data();
      v_plane = v_full.data();
    }
    uint8_t* out = rgb + 3 * tc * view;
    for (size_t i = 0; i < view; ++i) {
      const Rgb8 p = YuvToRgb(block.colour, y_plane[i], u_plane[i], v_plane[i], block.sample_frac);
      out[3 * i] = p.r;
      out[3 * i + 1] = p.g;
      out[3 * i + 2] = p.b;
    }
  }
}

}  // namespace fvv
