#include "codec/sa_wavelet.h"

#include <algorithm>

namespace fvv {
namespace {

// One pass over the lines of the region [0, w) x [0, h): along x when `rows`,
// else along y. `in_mask` gives the runs; writes `out_mask` (whole plane,
// region part replaced). Forward or inverse per `forward`.
void Pass(WaveletKernel kernel, bool forward, bool rows, uint32_t plane_width, uint32_t w,
          uint32_t h, const std::vector<uint8_t>& in_mask, std::vector<uint8_t>* out_mask,
          int32_t* data) {
  const uint32_t lines = rows ? h : w, length = rows ? w : h;
  const uint32_t half = (length + 1) / 2;
  const auto at = [&](uint32_t line, uint32_t i) {
    return rows ? size_t(line) * plane_width + i : size_t(i) * plane_width + line;
  };
  std::vector<int32_t> line_in(length), line_out(length), buf(length);
  std::vector<uint8_t> mask_out(length);
  for (uint32_t l = 0; l < lines; ++l) {
    for (uint32_t i = 0; i < length; ++i) line_in[i] = data[at(l, i)];
    std::fill(line_out.begin(), line_out.end(), 0);
    std::fill(mask_out.begin(), mask_out.end(), 0);
    uint32_t i = 0;
    while (i < length) {
      if (!in_mask[at(l, i)]) {
        ++i;
        continue;
      }
      uint32_t e = i;
      while (e < length && in_mask[at(l, e)]) ++e;
      const uint32_t m = e - i, ns = (m + 1) / 2, nd = m / 2, base = i / 2;
      if (forward) {
        // Deinterleave (evens, then odds), lift, place.
        for (uint32_t k = 0; k < ns; ++k) buf[k] = line_in[i + 2 * k];
        for (uint32_t k = 0; k < nd; ++k) buf[ns + k] = line_in[i + 2 * k + 1];
        LiftForward(kernel, m, 1, buf.data());
        for (uint32_t k = 0; k < ns; ++k) line_out[base + k] = buf[k], mask_out[base + k] = 1;
        for (uint32_t k = 0; k < nd; ++k) {
          line_out[half + base + k] = buf[ns + k];
          mask_out[half + base + k] = 1;
        }
      } else {
        for (uint32_t k = 0; k < ns; ++k) buf[k] = line_in[base + k];
        for (uint32_t k = 0; k < nd; ++k) buf[ns + k] = line_in[half + base + k];
        LiftInverse(kernel, m, 1, buf.data());
        for (uint32_t k = 0; k < ns; ++k) line_out[i + 2 * k] = buf[k];
        for (uint32_t k = 0; k < nd; ++k) line_out[i + 2 * k + 1] = buf[ns + k];
        for (uint32_t k = i; k < e; ++k) mask_out[k] = 1;
      }
      i = e;
    }
    for (uint32_t k = 0; k < length; ++k) {
      data[at(l, k)] = line_out[k];
      if (out_mask) (*out_mask)[at(l, k)] = mask_out[k];
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
  // The masks follow from running the forward passes on zeros.
  std::vector<std::vector<uint8_t>> out{mask};
  std::vector<int32_t> zeros(size_t(width) * height, 0);
  for (int l = 0; l < levels; ++l) {
    const uint32_t w = LevelExtent(width, l), h = LevelExtent(height, l);
    for (bool rows : {true, false}) {
      std::vector<uint8_t> next = out.back();
      Pass(WaveletKernel::kHaar, true, rows, width, w, h, out.back(), &next, zeros.data());
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
