// The coding order and context models of the mask coder (SPEC.md 7), written
// once for both sides. Mode 1: `Side::Flag(bit, prob)` encodes `bit` or decodes
// and returns a bit, adapting `prob`. Mode 2 (SPEC.md 7.2): `Side::Code(bit,
// prob_zero)` codes with a probability the traversal computes by mixing two
// count-adaptive models, and adapts them itself.
#ifndef FVV_CODEC_MASK_COMMON_H_
#define FVV_CODEC_MASK_COMMON_H_

#include <cstring>
#include <vector>

#include "codec/block.h"
#include "codec/logistic_mixing.h"
#include "codec/range_coder.h"

namespace fvv {
namespace mask {

constexpr int kPad = 4;  // zero texels around each padded plane (mode 2 reads x - 4)

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

// ---- Mode 2: two context models per texel, mixed in the logistic domain ----

enum RowMode : uint8_t { kRowCoded = 0, kRowCopied = 1, kRowRepeated = 2 };

struct MixingContexts {
  using P = mixing::CountedProb;
  // [previous row's flag + 2 * (the row tested against is all zero)
  //  + 4 * (the reference's row y was decided the same way)]
  P row_copy[8];
  P row_above[2][8];  // [has reference][as row_copy]
  std::vector<P> intra_small = std::vector<P>(1u << 10), intra_large = std::vector<P>(1u << 18);
  std::vector<P> inter_small = std::vector<P>(1u << 12), inter_large = std::vector<P>(1u << 20);
};

// A mask of a fragment with what its successors read: the row modes it was
// coded with.
struct CodedMask {
  CodedMask(uint32_t h, uint32_t w) : plane(h, w), modes(h, kRowCoded) {}
  PaddedPlane plane;
  std::vector<uint8_t> modes;
};

// Inlined by hand-holding: it runs once per coded texel.
#if defined(__GNUC__)
#define FVV_MASK_INLINE inline __attribute__((always_inline))
#else
#define FVV_MASK_INLINE inline
#endif

template <class Side>
FVV_MASK_INLINE uint32_t CodeMixed(Side& side, const mixing::MixTables& st, uint32_t bit,
                                   mixing::CountedProb* a, mixing::CountedProb* b) {
  bit = side.Code(bit, st.MixedProbZero(*a, *b));
  mixing::Update(bit, a);
  mixing::Update(bit, b);
  return bit;
}

template <class Side>
uint32_t CodeCounted(Side& side, uint32_t bit, mixing::CountedProb* m) {
  bit = side.Code(bit, m->p0);
  mixing::Update(bit, m);
  return bit;
}

inline bool AllZero(const uint8_t* row, uint32_t w) { return std::memchr(row, 1, w) == nullptr; }

// Codes one mask in mode 2. `ref` is the reference (as in mode 1) or null;
// `ref2` is the same camera two frames back, or `ref` where there is none.
template <class Side>
void CodeMaskMixing(Side& side, MixingContexts& ctx, uint32_t h, uint32_t w, const CodedMask* ref,
                    const PaddedPlane* ref2, CodedMask* cur) {
  uint32_t prev_copied = 0, prev_above = 0;
  const uint32_t has_ref = ref != nullptr;
  const mixing::MixTables& st = mixing::Tables();
  for (uint32_t y = 0; y < h; ++y) {
    uint8_t* row = cur->plane.Row(y);
    const uint8_t* up = cur->plane.Row(int64_t{y} - 1);  // zeros above row 0
    const uint32_t ref_mode = ref ? ref->modes[y] : uint32_t{kRowCoded};
    if (ref) {
      const uint8_t* source = ref->plane.Row(y);
      const uint32_t c = prev_copied + 2 * AllZero(source, w) + 4 * (ref_mode == kRowCopied);
      const uint32_t same = CodeCounted(side, std::memcmp(row, source, w) == 0, &ctx.row_copy[c]);
      prev_copied = same;
      if (same) {
        std::memcpy(row, source, w);
        cur->modes[y] = kRowCopied;
        continue;
      }
    }
    const uint32_t c = prev_above + 2 * AllZero(up, w) + 4 * (ref_mode == kRowRepeated);
    const uint32_t repeat =
        CodeCounted(side, std::memcmp(row, up, w) == 0, &ctx.row_above[has_ref][c]);
    prev_above = repeat;
    if (repeat) {
      std::memcpy(row, up, w);
      cur->modes[y] = kRowRepeated;
      continue;
    }
    cur->modes[y] = kRowCoded;
    // The templates as sliding windows over their rows (SPEC.md 7.2): each
    // window shifts left by one per texel and takes the texel entering on the
    // right, so bit 0 is the rightmost texel of the window.
    const uint8_t* up2 = cur->plane.Row(int64_t{y} - 2);
    uint32_t left = 0;  // M(x-1..x-4), bit 0 = x-1
    uint32_t above = up[-3] << 5 | up[-2] << 4 | up[-1] << 3 | up[0] << 2 | up[1] << 1 | up[2];
    if (ref) {
      const uint8_t* r0 = ref->plane.Row(y);
      const uint8_t* rn = ref->plane.Row(int64_t{y} - 1);
      const uint8_t* rs = ref->plane.Row(int64_t{y} + 1);
      const uint8_t* q0 = ref2->Row(y);
      uint32_t same = r0[-2] << 3 | r0[-1] << 2 | r0[0] << 1 | r0[1];  // R(x-2..x+2)
      uint32_t north = rn[-1] << 1 | rn[0];                            // R(x-1..x+1, y-1)
      uint32_t south = rs[-1] << 1 | rs[0];                            // R(x-1..x+1, y+1)
      uint32_t moved = (q0[-1] ^ r0[-1]) << 1 | (q0[0] ^ r0[0]);       // R2 ^ R at x-1..x+1
      for (int64_t x = 0; x < int64_t{w}; ++x) {
        above = (above << 1 | up[x + 3]) & 127;  // M(x-3..x+3, y-1)
        same = (same << 1 | r0[x + 2]) & 31;
        north = (north << 1 | rn[x + 1]) & 7;
        south = (south << 1 | rs[x + 1]) & 7;
        moved = (moved << 1 | (q0[x + 1] ^ r0[x + 1])) & 7;
        const uint32_t small = (left & 3) | (above >> 2 & 7) << 2 | (same >> 1 & 7) << 5 |
                               (north >> 1 & 1) << 8 | (south >> 1 & 1) << 9 |
                               (moved >> 1 & 1) << 10 | ((moved | moved >> 2) & 1) << 11;
        const uint32_t large = (left & 7) | (above >> 1 & 31) << 3 | same << 8 | north << 13 |
                               south << 16 | (moved >> 1 & 1) << 19;
        const uint32_t bit =
            CodeMixed(side, st, row[x], &ctx.inter_small[small], &ctx.inter_large[large]);
        row[x] = static_cast<uint8_t>(bit);
        left = (left << 1 | bit) & 15;
      }
    } else {
      uint32_t above2 = up2[-3] << 5 | up2[-2] << 4 | up2[-1] << 3 | up2[0] << 2 | up2[1] << 1 |
                        up2[2];  // M(x-3..x+3, y-2)
      for (int64_t x = 0; x < int64_t{w}; ++x) {
        above = (above << 1 | up[x + 3]) & 127;
        above2 = (above2 << 1 | up2[x + 3]) & 127;
        const uint32_t small = (left & 3) | (above >> 1 & 31) << 2 | (above2 >> 2 & 7) << 7;
        const uint32_t large = left | above << 4 | above2 << 11;
        const uint32_t bit =
            CodeMixed(side, st, row[x], &ctx.intra_small[small], &ctx.intra_large[large]);
        row[x] = static_cast<uint8_t>(bit);
        left = (left << 1 | bit) & 15;
      }
    }
  }
}

// Mode 2's traversal: the order and references of mode 1, plus each camera's
// mask two frames back.
template <class Side, class Load, class Store>
void TraverseMasksMixing(Side& side, const Shape4D& shape, Load load, Store store) {
  const uint32_t h = shape.height(), w = shape.width();
  MixingContexts ctx;
  std::vector<CodedMask> prev(shape.cameras(), CodedMask(h, w));
  std::vector<PaddedPlane> prev2(shape.cameras(), PaddedPlane(h, w));
  CodedMask cur(h, w);
  for (uint32_t t = 0; t < shape.frames(); ++t) {
    for (uint32_t c = 0; c < shape.cameras(); ++c) {
      load(t, c, &cur.plane);
      const CodedMask* ref = t > 0 ? &prev[c] : c > 0 ? &prev[c - 1] : nullptr;
      const PaddedPlane* ref2 = t > 1 ? &prev2[c] : ref ? &ref->plane : nullptr;
      CodeMaskMixing(side, ctx, h, w, ref, ref2, &cur);
      if (!side.ok()) return;
      store(t, c, cur.plane);
      std::swap(prev2[c], prev[c].plane);
      std::swap(prev[c], cur);
    }
  }
}

}  // namespace mask
}  // namespace fvv

#endif  // FVV_CODEC_MASK_COMMON_H_
