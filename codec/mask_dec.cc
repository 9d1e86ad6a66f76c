#include <cstring>

#include "codec/mask.h"
#include "codec/mask_common.h"

namespace fvv {
namespace {

class Reader {
 public:
  Reader(const uint8_t* data, size_t size) : rc_(data, size) {}
  uint32_t Flag(uint32_t, uint16_t* p) { return rc_.Decode(p); }
  uint32_t Code(uint32_t, uint32_t prob_zero) { return rc_.DecodeWithProbability(prob_zero); }
  bool ok() const { return rc_.ok(); }
  RangeDecoder rc_;
};

}  // namespace

Status DecodeMasks(const uint8_t* data, size_t size, const Shape4D& shape, MaskCoding mode,
                   uint8_t* out) {
  if (mode != MaskCoding::kContext && mode != MaskCoding::kMixing) {
    return Unsupported("mask mode " + std::to_string(static_cast<int>(mode)));
  }
  Reader r(data, size);
  const uint32_t h = shape.height(), w = shape.width();
  const auto load = [](uint32_t, uint32_t, mask::PaddedPlane*) {};
  const auto store = [&](uint32_t t, uint32_t c, const mask::PaddedPlane& plane) {
    for (uint32_t y = 0; y < h; ++y) std::memcpy(out + shape.Index(t, c, y, 0), plane.Row(y), w);
  };
  if (mode == MaskCoding::kContext) {
    mask::TraverseMasks(r, shape, load, store);
  } else {
    mask::TraverseMasksMixing(r, shape, load, store);
  }
  if (!r.rc_.ok()) {
    return Corrupt("mask data: " + std::to_string(size) + " bytes end before the last of " +
                   std::to_string(shape.frames() * shape.cameras()) + " masks");
  }
  return Status::Ok();
}

}  // namespace fvv
