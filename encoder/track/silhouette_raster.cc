#include "encoder/track/silhouette_raster.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace fvv {

namespace {

// Fills the rows y0..y1, columns x0..x1 (already clipped to the image) of one
// front-facing triangle with signed area `area`.
inline void FillTriangle(const Eigen::Vector2f& a, const Eigen::Vector2f& b,
                         const Eigen::Vector2f& c, float area, int x0, int y0, int x1, int y1,
                         int w, uint8_t* out) {
  const float inv = 1.0f / area;
#if defined(__SSE2__)
  // PixelInTriangle on four pixels of a row at once: the same IEEE single
  // operations in the same order (the build keeps them unfused), so every
  // lane equals the scalar test. The products that depend on y alone are
  // taken once per row.
  const float cbx = c.x() - b.x(), cby = c.y() - b.y(), acx = a.x() - c.x(), acy = a.y() - c.y();
  const __m128 v_inv = _mm_set1_ps(inv), v_bx = _mm_set1_ps(b.x()), v_cx = _mm_set1_ps(c.x());
  const __m128 v_cby = _mm_set1_ps(cby), v_acy = _mm_set1_ps(acy);
  const __m128 zero = _mm_setzero_ps(), one = _mm_set1_ps(1.0f);
  const __m128 lane = _mm_setr_ps(0, 1, 2, 3);
  // Byte masks of the 16 four-pixel patterns (in x86's little-endian byte
  // order: lane i is byte i), OR-ed into the row where four bytes fit inside it.
  static constexpr uint32_t kBytes[16] = {0x00000000, 0x00000001, 0x00000100, 0x00000101,
                                          0x00010000, 0x00010001, 0x00010100, 0x00010101,
                                          0x01000000, 0x01000001, 0x01000100, 0x01000101,
                                          0x01010000, 0x01010001, 0x01010100, 0x01010101};
  for (int y = y0; y <= y1; ++y) {
    const __m128 row0 = _mm_set1_ps(cbx * (y - b.y())), row1 = _mm_set1_ps(acx * (y - c.y()));
    uint8_t* row = out + size_t(y) * w;
    for (int x = x0; x <= x1; x += 4) {
      // x + lane is exact in float (x < 2^24): the same value as float(x + i).
      const __m128 vx = _mm_add_ps(_mm_set1_ps(float(x)), lane);
      const __m128 w0 =
          _mm_mul_ps(_mm_sub_ps(row0, _mm_mul_ps(v_cby, _mm_sub_ps(vx, v_bx))), v_inv);
      const __m128 w1 =
          _mm_mul_ps(_mm_sub_ps(row1, _mm_mul_ps(v_acy, _mm_sub_ps(vx, v_cx))), v_inv);
      const __m128 in = _mm_and_ps(_mm_and_ps(_mm_cmpge_ps(w0, zero), _mm_cmpge_ps(w1, zero)),
                                   _mm_cmple_ps(_mm_add_ps(w0, w1), one));
      unsigned bits = unsigned(_mm_movemask_ps(in));
      if (x1 - x < 3) bits &= (1u << (x1 - x + 1)) - 1;  // lanes past the box
      if (x + 3 < w) {
        uint32_t word;
        std::memcpy(&word, row + x, 4);
        word |= kBytes[bits];
        std::memcpy(row + x, &word, 4);
      } else {
        for (; bits != 0; bits &= bits - 1) row[x + __builtin_ctz(bits)] = 1;
      }
    }
  }
#else
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      if (PixelInTriangle(a, b, c, inv, x, y)) out[size_t(y) * w + x] = 1;
    }
  }
#endif
}

// The clipped bounding box of a triangle with extent [lo, hi] on one axis of
// an image n pixels long: ceil(lo) .. floor(hi), within 0 .. n - 1. Clamping
// first keeps far-off vertices (behind-camera projections) from overflowing
// the conversion; it does not change the clipped result.
inline int FirstPixel(float lo, int n) {
  return int(std::ceil(std::min(std::max(lo, -1.0f), float(n))));
}
inline int LastPixel(float hi, int n) {
  return int(std::floor(std::min(std::max(hi, -1.0f), float(n))));
}

}  // namespace

void RasteriseSilhouette(const std::vector<uint32_t>& tris, const std::vector<Eigen::Vector2f>& px,
                         int w, int h, uint8_t* out, RasterBox* box) {
  size_t t = 0;
#if defined(__SSE2__)
  // Four triangles at a time up to the fill: area (the same float operations
  // as the scalar path) and clipped bounding box, so that back faces and
  // triangles between pixel centres (most of a mesh at tracking resolution)
  // cost a few vector operations each.
  const __m128 v_lo = _mm_set1_ps(-1.0f), v_wf = _mm_set1_ps(float(w)),
               v_hf = _mm_set1_ps(float(h));
  const __m128 v_one = _mm_set1_ps(1.0f);
  auto ceil4 = [&](__m128 v) {  // exact for |v| < 2^31
    const __m128 tr = _mm_cvtepi32_ps(_mm_cvttps_epi32(v));
    return _mm_add_ps(tr, _mm_and_ps(_mm_cmplt_ps(tr, v), v_one));
  };
  auto floor4 = [&](__m128 v) {
    const __m128 tr = _mm_cvtepi32_ps(_mm_cvttps_epi32(v));
    return _mm_sub_ps(tr, _mm_and_ps(_mm_cmpgt_ps(tr, v), v_one));
  };
  auto load2 = [&](uint32_t i0, uint32_t i1) {
    __m128 v = _mm_setzero_ps();
    v = _mm_loadl_pi(v, reinterpret_cast<const __m64*>(px[i0].data()));
    return _mm_loadh_pi(v, reinterpret_cast<const __m64*>(px[i1].data()));
  };
  for (; t + 12 <= tris.size(); t += 12) {
    const uint32_t* ix = &tris[t];
    const __m128 a01 = load2(ix[0], ix[3]), a23 = load2(ix[6], ix[9]);
    const __m128 b01 = load2(ix[1], ix[4]), b23 = load2(ix[7], ix[10]);
    const __m128 c01 = load2(ix[2], ix[5]), c23 = load2(ix[8], ix[11]);
    const __m128 ax = _mm_shuffle_ps(a01, a23, _MM_SHUFFLE(2, 0, 2, 0));
    const __m128 ay = _mm_shuffle_ps(a01, a23, _MM_SHUFFLE(3, 1, 3, 1));
    const __m128 bx = _mm_shuffle_ps(b01, b23, _MM_SHUFFLE(2, 0, 2, 0));
    const __m128 by = _mm_shuffle_ps(b01, b23, _MM_SHUFFLE(3, 1, 3, 1));
    const __m128 cx = _mm_shuffle_ps(c01, c23, _MM_SHUFFLE(2, 0, 2, 0));
    const __m128 cy = _mm_shuffle_ps(c01, c23, _MM_SHUFFLE(3, 1, 3, 1));
    const __m128 area = _mm_sub_ps(_mm_mul_ps(_mm_sub_ps(bx, ax), _mm_sub_ps(cy, ay)),
                                   _mm_mul_ps(_mm_sub_ps(by, ay), _mm_sub_ps(cx, ax)));
    auto clamp = [&](__m128 v, __m128 n) { return _mm_min_ps(_mm_max_ps(v, v_lo), n); };
    const __m128 fx0 = ceil4(clamp(_mm_min_ps(_mm_min_ps(ax, bx), cx), v_wf));
    const __m128 fx1 = floor4(clamp(_mm_max_ps(_mm_max_ps(ax, bx), cx), v_wf));
    const __m128 fy0 = ceil4(clamp(_mm_min_ps(_mm_min_ps(ay, by), cy), v_hf));
    const __m128 fy1 = floor4(clamp(_mm_max_ps(_mm_max_ps(ay, by), cy), v_hf));
    // Front facing, and a pixel centre in the box once clipped to the image.
    const __m128 keep =
        _mm_and_ps(_mm_and_ps(_mm_cmplt_ps(area, _mm_setzero_ps()),
                              _mm_and_ps(_mm_cmple_ps(_mm_max_ps(fx0, _mm_setzero_ps()),
                                                      _mm_min_ps(fx1, _mm_sub_ps(v_wf, v_one))),
                                         _mm_cmple_ps(_mm_max_ps(fy0, _mm_setzero_ps()),
                                                      _mm_min_ps(fy1, _mm_sub_ps(v_hf, v_one))))),
                   _mm_cmpord_ps(area, area));
    unsigned bits = unsigned(_mm_movemask_ps(keep));
    if (bits == 0) continue;
    alignas(16) float areas[4];
    alignas(16) int32_t x0s[4], x1s[4], y0s[4], y1s[4];
    _mm_store_ps(areas, area);
    _mm_store_si128(reinterpret_cast<__m128i*>(x0s), _mm_cvttps_epi32(fx0));
    _mm_store_si128(reinterpret_cast<__m128i*>(x1s), _mm_cvttps_epi32(fx1));
    _mm_store_si128(reinterpret_cast<__m128i*>(y0s), _mm_cvttps_epi32(fy0));
    _mm_store_si128(reinterpret_cast<__m128i*>(y1s), _mm_cvttps_epi32(fy1));
    for (; bits != 0; bits &= bits - 1) {
      const int k = __builtin_ctz(bits);
      const int x0 = std::max(0, x0s[k]), x1 = std::min(w - 1, x1s[k]);
      const int y0 = std::max(0, y0s[k]), y1 = std::min(h - 1, y1s[k]);
      box->x0 = std::min(box->x0, x0), box->x1 = std::max(box->x1, x1);
      box->y0 = std::min(box->y0, y0), box->y1 = std::max(box->y1, y1);
      FillTriangle(px[ix[3 * k]], px[ix[3 * k + 1]], px[ix[3 * k + 2]], areas[k], x0, y0, x1, y1, w,
                   out);
    }
  }
#endif
  for (; t + 2 < tris.size(); t += 3) {
    const Eigen::Vector2f a = px[tris[t]], b = px[tris[t + 1]], c = px[tris[t + 2]];
    const float area = (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
    // Outward counter-clockwise winding appears clockwise in y-down images: a
    // closed mesh's silhouette is the union of its front faces (area < 0).
    if (!(area < 0)) continue;
    const int x0 = std::max(0, FirstPixel(std::min({a.x(), b.x(), c.x()}), w));
    const int x1 = std::min(w - 1, LastPixel(std::max({a.x(), b.x(), c.x()}), w));
    const int y0 = std::max(0, FirstPixel(std::min({a.y(), b.y(), c.y()}), h));
    const int y1 = std::min(h - 1, LastPixel(std::max({a.y(), b.y(), c.y()}), h));
    if (x0 > x1 || y0 > y1) continue;
    box->x0 = std::min(box->x0, x0), box->x1 = std::max(box->x1, x1);
    box->y0 = std::min(box->y0, y0), box->y1 = std::max(box->y1, y1);
    FillTriangle(a, b, c, area, x0, y0, x1, y1, w, out);
  }
}

}  // namespace fvv
