#include <algorithm>
#include <cstdlib>

#include "codec/bisk.h"
#include "codec/bisk_common.h"

namespace fvv {

std::vector<uint8_t> BiskEncode(const ShapePlane& image, WaveletKernel kernel, int levels,
                                std::vector<size_t>* plane_ends) {
  ShapePlane p = image;
  ForwardShapeAdaptive(kernel, levels, &p);
  const bisk::SubbandShifts shifts(p.width, p.height, levels);
  for (uint32_t y = 0; y < p.height; ++y) {
    for (uint32_t x = 0; x < p.width; ++x) {
      const size_t i = size_t(y) * p.width + x;
      p.samples[i] *= int32_t(1) << shifts(x, y);
    }
  }
  int32_t max = 0;
  for (size_t i = 0; i < p.samples.size(); ++i) {
    if (p.mask[i]) max = std::max(max, std::abs(p.samples[i]));
  }
  std::vector<uint8_t> out;
  if (max == 0) {
    out.push_back(255);
    if (plane_ends) plane_ends->assign(1, 1);
    return out;
  }
  const int top = bisk::Log2Floor(uint64_t(max));
  out.push_back(uint8_t(top));
  RangeEncoder enc;
  bisk::BiskCoder<true> coder(p.width, p.height, p.mask, levels, p.samples.data(), &enc, nullptr);
  std::vector<size_t> ends;
  coder.set_plane_ends(&ends);
  coder.Run(top);
  const std::vector<uint8_t> body = enc.Finish();
  out.insert(out.end(), body.begin(), body.end());
  if (plane_ends) {
    // The range coder counts the bytes of its own stream; the header byte
    // comes before it.
    plane_ends->clear();
    for (size_t e : ends) plane_ends->push_back(std::min(out.size(), 1 + e));
  }
  return out;
}

}  // namespace fvv
