#include "codec/block.h"

namespace fvv {

std::string Shape4D::ToString() const {
  return std::to_string(n[0]) + "x" + std::to_string(n[1]) + "x" + std::to_string(n[2]) + "x" +
         std::to_string(n[3]) + " (frames x cameras x height x width)";
}

Shape4D ChromaShape(const Shape4D& luma, ChromaFormat format) {
  Shape4D s = luma;
  if (format == ChromaFormat::k420) {
    s.n[2] = (s.n[2] + 1) / 2;
    s.n[3] = (s.n[3] + 1) / 2;
  }
  return s;
}

SampleRange ChannelRange(ColourSpace colour, int channel, int sample_frac) {
  if (colour == ColourSpace::kRct && channel > 0) return {-255, 255, 0, 0};
  return {0, 255 << sample_frac, 128 << sample_frac, sample_frac};
}

}  // namespace fvv
