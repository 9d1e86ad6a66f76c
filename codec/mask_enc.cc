#include "codec/mask.h"
#include "codec/mask_common.h"

namespace fvv {
namespace {

class Writer {
 public:
  uint32_t Flag(uint32_t bit, uint16_t* p) {
    rc_.Encode(bit, p);
    return bit;
  }
  uint32_t Code(uint32_t bit, uint32_t prob_zero) {
    rc_.EncodeWithProbability(bit, prob_zero);
    return bit;
  }
  bool ok() const { return true; }
  RangeEncoder rc_;
};

}  // namespace

std::vector<uint8_t> EncodeMasks(const uint8_t* masks, const Shape4D& shape, MaskCoding mode) {
  Writer w;
  const uint32_t h = shape.height(), width = shape.width();
  const auto load = [&](uint32_t t, uint32_t c, mask::PaddedPlane* plane) {
    for (uint32_t y = 0; y < h; ++y) {
      const uint8_t* src = masks + shape.Index(t, c, y, 0);
      uint8_t* dst = plane->Row(y);
      for (uint32_t x = 0; x < width; ++x) dst[x] = src[x] != 0;
    }
  };
  const auto store = [](uint32_t, uint32_t, const mask::PaddedPlane&) {};
  if (mode == MaskCoding::kContext) {
    mask::TraverseMasks(w, shape, load, store);
  } else {
    mask::TraverseMasksMixing(w, shape, load, store);
  }
  return w.rc_.Finish();
}

}  // namespace fvv
