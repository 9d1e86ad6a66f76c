// The coding order and context model of the mask coder (SPEC.md 7), written
// once for both sides: `Side::Flag(bit, prob)` encodes `bit` or decodes and
// returns a bit.
#ifndef FVV_CODEC_MASK_TRAVERSAL_H_
#define FVV_CODEC_MASK_TRAVERSAL_H_

#include <cstring>
#include <vector>

#include "codec/block.h"
#include "codec/range_coder.h"

namespace fvv {
namespace mask {

constexpr int kPad = 2;  // zero texels around each padded plane

// A mask with kPad zero columns left and right, kPad zero rows above and below.
class PaddedPlane {
 public:
  PaddedPlane(uint32_t h, uint32_t w) : stride_(w + 2 * kPad), v_((h + 2 * kPad) * stride_, 0) {}
  uint8_t* Row(int64_t y) { return v_.data() + (y + kPad) * stride_ + kPad; }
  const uint8_t* Row(int64_t y) const { return v_.data() + (y + kPad) * stride_ + kPad; }

 private:
  size_t stride_;
  std::vector<uint8_t> v_;
};

struct Contexts {
  Contexts() {
    for (auto& p : intra) p = kProbInit;
    for (auto& p : inter) p = kProbInit;
    row_copy[0] = row_copy[1] = kProbInit;
    for (auto& r : row_above) r[0] = r[1] = kProbInit;
  }
  uint16_t intra[1 << 10];
  uint16_t inter[1 << 10];
  uint16_t row_copy[2];      // [previous row was copied]
  uint16_t row_above[2][2];  // [has reference][previous row repeated the row above]
};

// Codes one mask. `ref` is the reference mask (SPEC.md 7: the same camera in the
// previous frame, or in a fragment's first frame the previous camera), or null.
// `cur` holds the mask (encoder) or receives it.
template <class Side>
void CodeMask(Side& side, Contexts& ctx, uint32_t h, uint32_t w, const PaddedPlane* ref,
              PaddedPlane* cur) {
  uint32_t prev_copied = 0, prev_above = 0;
  const uint32_t has_ref = ref != nullptr;
  for (uint32_t y = 0; y < h; ++y) {
    uint8_t* row = cur->Row(y);
    const uint8_t* above = cur->Row(int64_t{y} - 1);  // zeros above row 0
    // A row equal to the reference's row, or else to the row above, costs one or
    // two decisions (without a reference, only the second test is made).
    if (ref) {
      const uint8_t* source = ref->Row(y);
      const uint32_t same = side.Flag(std::memcmp(row, source, w) == 0, &ctx.row_copy[prev_copied]);
      prev_copied = same;
      if (same) {
        std::memcpy(row, source, w);
        continue;
      }
    }
    const uint32_t repeat =
        side.Flag(std::memcmp(row, above, w) == 0, &ctx.row_above[has_ref][prev_above]);
    prev_above = repeat;
    if (repeat) {
      std::memcpy(row, above, w);
      continue;
    }
    const uint8_t* up = cur->Row(int64_t{y} - 1);
    const uint8_t* up2 = cur->Row(int64_t{y} - 2);
    if (ref) {
      const uint8_t* r0 = ref->Row(y);
      const uint8_t* rn = ref->Row(int64_t{y} - 1);
      const uint8_t* rs = ref->Row(int64_t{y} + 1);
      for (int64_t x = 0; x < int64_t{w}; ++x) {
        const uint32_t c = row[x - 1] | row[x - 2] << 1 | up[x - 1] << 2 | up[x] << 3 |
                           up[x + 1] << 4 | r0[x] << 5 | r0[x - 1] << 6 | r0[x + 1] << 7 |
                           rn[x] << 8 | rs[x] << 9;
        row[x] = static_cast<uint8_t>(side.Flag(row[x], &ctx.inter[c]));
      }
    } else {
      for (int64_t x = 0; x < int64_t{w}; ++x) {
        const uint32_t c = row[x - 1] | row[x - 2] << 1 | up[x - 2] << 2 | up[x - 1] << 3 |
                           up[x] << 4 | up[x + 1] << 5 | up[x + 2] << 6 | up2[x - 1] << 7 |
                           up2[x] << 8 | up2[x + 1] << 9;
        row[x] = static_cast<uint8_t>(side.Flag(row[x], &ctx.intra[c]));
      }
    }
  }
}

// Codes all masks of a fragment in (t, c) order. `load(t, c, plane)` fills the
// plane before coding (encoder); `store(t, c, plane)` takes the result.
template <class Side, class Load, class Store>
void TraverseMasks(Side& side, const Shape4D& shape, Load load, Store store) {
  const uint32_t h = shape.height(), w = shape.width();
  Contexts ctx;
  std::vector<PaddedPlane> prev(shape.cameras(), PaddedPlane(h, w));
  PaddedPlane cur(h, w);
  for (uint32_t t = 0; t < shape.frames(); ++t) {
    for (uint32_t c = 0; c < shape.cameras(); ++c) {
      load(t, c, &cur);
      // In the first frame, neighbouring cameras see much of the same surface.
      const PaddedPlane* ref = t > 0 ? &prev[c] : c > 0 ? &prev[c - 1] : nullptr;
      CodeMask(side, ctx, h, w, ref, &cur);
      if (!side.ok()) return;  // a decoder past its data: stop, the caller reports it
      store(t, c, cur);
      std::swap(prev[c], cur);
    }
  }
}

}  // namespace mask
}  // namespace fvv

#endif  // FVV_CODEC_MASK_TRAVERSAL_H_
