#include <cstring>

#include "codec/mask_coder.h"
#include "codec/mask_traversal.h"

namespace fvv {
namespace {

class Reader {
 public:
  Reader(const uint8_t* data, size_t size) : rc_(data, size) {}
  uint32_t Flag(uint32_t, uint16_t* p) { return rc_.Decode(p); }
  bool ok() const { return rc_.ok(); }
  RangeDecoder rc_;
};

}  // namespace

Status DecodeMasks(const uint8_t* data, size_t size, const Shape4D& shape, uint8_t* out) {
  Reader r(data, size);
  const uint32_t h = shape.height(), w = shape.width();
  mask::TraverseMasks(
      r, shape, [](uint32_t, uint32_t, mask::PaddedPlane*) {},
      [&](uint32_t t, uint32_t c, const mask::PaddedPlane& plane) {
        for (uint32_t y = 0; y < h; ++y)
          std::memcpy(out + shape.Index(t, c, y, 0), plane.Row(y), w);
      });
  if (!r.rc_.ok()) {
    return Truncated("mask data: " + std::to_string(size) + " bytes end before the last of " +
                     std::to_string(shape.frames() * shape.cameras()) + " masks");
  }
  return Status::Ok();
}

}  // namespace fvv
