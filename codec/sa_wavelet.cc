#include "codec/sa_wavelet.h"

#include <algorithm>

namespace fvv {
namespace {

// One line of `length` samples: its runs of in-mask samples lifted on their
// own (forward: to the low and high halves; inverse: back). `in`/`in_mask`
// and `out`/`out_mask` are contiguous; `data` may be null (masks only).
void Line(WaveletKernel kernel, bool forward, uint32_t length, const int32_t* in,
          const uint8_t* in_mask, int32_t* out, uint8_t* out_mask, int32_t* buf) {
  const uint32_t half = (length + 1) / 2;
  if (out) std::fill(out, out + length, 0);
  if (out_mask) std::fill(out_mask, out_mask + length, 0);
  uint32_t i = 0;
  while (i < length) {
    if (!in_mask[i]) {
      ++i;
      continue;
    }
    uint32_t e = i;
    while (e < length && in_mask[e]) ++e;
    const uint32_t m = e - i, ns = (m + 1) / 2, nd = m / 2, base = i / 2;
    if (forward) {
      if (out) {
        // Deinterleave (evens, then odds), lift, place.
        for (uint32_t k = 0; k < ns; ++k) buf[k] = in[i + 2 * k];
        for (uint32_t k = 0; k < nd; ++k) buf[ns + k] = in[i + 2 * k + 1];
        LiftForward(kernel, m, 1, buf);
        std::copy(buf, buf + ns, out + base);
        std::copy(buf + ns, buf + m, out + half + base);
      }
      if (out_mask) {
        std::fill(out_mask + base, out_mask + base + ns, 1);
        std::fill(out_mask + half + base, out_mask + half + base + nd, 1);
      }
    } else {
      if (out) {
        std::copy(in + base, in + base + ns, buf);
        std::copy(in + half + base, in + half + base + nd, buf + ns);
        LiftInverse(kernel, m, 1, buf);
        for (uint32_t k = 0; k < ns; ++k) out[i + 2 * k] = buf[k];
        for (uint32_t k = 0; k < nd; ++k) out[i + 2 * k + 1] = buf[ns + k];
      }
      if (out_mask) std::fill(out_mask + i, out_mask + e, 1);
    }
    i = e;
  }
}

// Columns are gathered this many at a time, so their strided reads share
// cache lines.
constexpr uint32_t kColumnGroup = 16;

// One pass over the lines of the region [0, w) x [0, h): along x when `rows`,
// else along y. `in_mask` gives the runs; writes `out_mask` (whole plane,
// region part replaced) when not null, and transforms `data` when not null.
void Pass(WaveletKernel kernel, bool forward, bool rows, uint32_t plane_width, uint32_t w,
          uint32_t h, const std::vector<uint8_t>& in_mask, std::vector<uint8_t>* out_mask,
          int32_t* data) {
  const uint32_t length = rows ? w : h;
  if (rows) {
    std::vector<int32_t> line(length), buf(length);
    for (uint32_t y = 0; y < h; ++y) {
      const size_t row = size_t(y) * plane_width;
      if (data) std::copy(data + row, data + row + length, line.begin());
      Line(kernel, forward, length, line.data(), &in_mask[row], data ? data + row : nullptr,
           out_mask ? &(*out_mask)[row] : nullptr, buf.data());
    }
    return;
  }
  const uint32_t g = kColumnGroup;
  std::vector<int32_t> lines(size_t(g) * length), outs(size_t(g) * length), buf(length);
  std::vector<uint8_t> masks(size_t(g) * length), mask_outs(size_t(g) * length);
  for (uint32_t x0 = 0; x0 < w; x0 += g) {
    const uint32_t n = std::min(g, w - x0);
    for (uint32_t y = 0; y < length; ++y) {
      const size_t at = size_t(y) * plane_width + x0;
      for (uint32_t k = 0; k < n; ++k) {
        masks[size_t(k) * length + y] = in_mask[at + k];
        if (data) lines[size_t(k) * length + y] = data[at + k];
      }
    }
    for (uint32_t k = 0; k < n; ++k) {
      const size_t o = size_t(k) * length;
      Line(kernel, forward, length, &lines[o], &masks[o], data ? &outs[o] : nullptr,
           out_mask ? &mask_outs[o] : nullptr, buf.data());
    }
    for (uint32_t y = 0; y < length; ++y) {
      const size_t at = size_t(y) * plane_width + x0;
      for (uint32_t k = 0; k < n; ++k) {
        if (data) data[at + k] = outs[size_t(k) * length + y];
        if (out_mask) (*out_mask)[at + k] = mask_outs[size_t(k) * length + y];
      }
    }
  }
}

uint32_t LevelExtent(uint32_t n, int level) {
  for (int l = 0; l < level; ++l) n = (n + 1) / 2;
  return n;
}

}  // namespace

int ShapeAdaptiveLevels(uint32_t width, uint32_t height) {
  int levels = 0;
  for (uint32_t s = std::min(width, height); s > 4 && levels < 6; s = (s + 1) / 2) ++levels;
  return levels;
}

std::vector<std::vector<uint8_t>> ShapeAdaptiveMasks(const std::vector<uint8_t>& mask,
                                                     uint32_t width, uint32_t height, int levels) {
  // The masks follow from the forward passes' runs alone.
  std::vector<std::vector<uint8_t>> out{mask};
  for (int l = 0; l < levels; ++l) {
    const uint32_t w = LevelExtent(width, l), h = LevelExtent(height, l);
    for (bool rows : {true, false}) {
      std::vector<uint8_t> next = out.back();
      Pass(WaveletKernel::kHaar, true, rows, width, w, h, out.back(), &next, nullptr);
      out.push_back(std::move(next));
    }
  }
  return out;
}

void ForwardShapeAdaptive(WaveletKernel kernel, int levels, ShapePlane* p) {
  for (size_t i = 0; i < p->samples.size(); ++i) {
    if (!p->mask[i]) p->samples[i] = 0;
  }
  for (int l = 0; l < levels; ++l) {
    const uint32_t w = LevelExtent(p->width, l), h = LevelExtent(p->height, l);
    for (bool rows : {true, false}) {
      std::vector<uint8_t> next = p->mask;
      Pass(kernel, true, rows, p->width, w, h, p->mask, &next, p->samples.data());
      p->mask = std::move(next);
    }
  }
}

void InverseShapeAdaptive(WaveletKernel kernel, int levels, const std::vector<uint8_t>& shape,
                          ShapePlane* p) {
  InverseShapeAdaptive(kernel, levels, ShapeAdaptiveMasks(shape, p->width, p->height, levels), p);
}

void InverseShapeAdaptive(WaveletKernel kernel, int levels,
                          const std::vector<std::vector<uint8_t>>& masks, ShapePlane* p) {
  for (int l = levels - 1; l >= 0; --l) {
    const uint32_t w = LevelExtent(p->width, l), h = LevelExtent(p->height, l);
    // Columns were transformed last: undone first, with the runs they had.
    Pass(kernel, false, false, p->width, w, h, masks[2 * l + 1], nullptr, p->samples.data());
    Pass(kernel, false, true, p->width, w, h, masks[2 * l], nullptr, p->samples.data());
  }
  p->mask = masks.front();
}

}  // namespace fvv
