// Growing a binary mask: every pixel within a square neighbourhood of a set
// one is set; shrinking is growing its complement. Separable (rows, then
// columns), so its cost does not grow with the square's area.
#ifndef FVV_ENCODER_ENCODE_MASK_DILATION_H_
#define FVV_ENCODER_ENCODE_MASK_DILATION_H_

#include <cstdint>
#include <vector>

namespace fvv {

// `mask`: w x h, row-major, non-0 = set. Returns 0/1, the same size, grown by
// `r` pixels; a negative `r` shrinks it by -r (what lies beyond the image
// counts as set, so the image's edge does not eat into it).
std::vector<uint8_t> DilateMask(const uint8_t* mask, int w, int h, int r);

}  // namespace fvv

#endif  // FVV_ENCODER_ENCODE_MASK_DILATION_H_
