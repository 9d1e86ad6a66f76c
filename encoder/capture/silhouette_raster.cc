#include "encoder/capture/silhouette_raster.h"

#include <algorithm>
#include <cmath>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace fvv {

void RasteriseSilhouette(const std::vector<uint32_t>& tris, const std::vector<Eigen::Vector2f>& px,
                         int w, int h, uint8_t* out, RasterBox* box) {
  for (size_t t = 0; t + 2 < tris.size(); t += 3) {
    const Eigen::Vector2f a = px[tris[t]], b = px[tris[t + 1]], c = px[tris[t + 2]];
    const float area = (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
    // Outward counter-clockwise winding appears clockwise in y-down images: a
    // closed mesh's silhouette is the union of its front faces (area < 0).
    if (!(area < 0)) continue;
    const int x0 = std::max(0, int(std::ceil(std::min({a.x(), b.x(), c.x()}))));
    const int x1 = std::min(w - 1, int(std::floor(std::max({a.x(), b.x(), c.x()}))));
    const int y0 = std::max(0, int(std::ceil(std::min({a.y(), b.y(), c.y()}))));
    const int y1 = std::min(h - 1, int(std::floor(std::max({a.y(), b.y(), c.y()}))));
    if (x0 > x1 || y0 > y1) continue;
    box->x0 = std::min(box->x0, x0), box->x1 = std::max(box->x1, x1);
    box->y0 = std::min(box->y0, y0), box->y1 = std::max(box->y1, y1);
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
    const __m128i lane = _mm_setr_epi32(0, 1, 2, 3);
    for (int y = y0; y <= y1; ++y) {
      const __m128 row0 = _mm_set1_ps(cbx * (y - b.y())), row1 = _mm_set1_ps(acx * (y - c.y()));
      uint8_t* row = out + size_t(y) * w;
      for (int x = x0; x <= x1; x += 4) {
        const __m128 vx = _mm_cvtepi32_ps(_mm_add_epi32(_mm_set1_epi32(x), lane));
        const __m128 w0 =
            _mm_mul_ps(_mm_sub_ps(row0, _mm_mul_ps(v_cby, _mm_sub_ps(vx, v_bx))), v_inv);
        const __m128 w1 =
            _mm_mul_ps(_mm_sub_ps(row1, _mm_mul_ps(v_acy, _mm_sub_ps(vx, v_cx))), v_inv);
        const __m128 in = _mm_and_ps(_mm_and_ps(_mm_cmpge_ps(w0, zero), _mm_cmpge_ps(w1, zero)),
                                     _mm_cmple_ps(_mm_add_ps(w0, w1), one));
        unsigned bits = unsigned(_mm_movemask_ps(in));
        if (x1 - x < 3) bits &= (1u << (x1 - x + 1)) - 1;  // lanes past the box
        for (; bits != 0; bits &= bits - 1) row[x + __builtin_ctz(bits)] = 1;
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
}

}  // namespace fvv
