// Lossless coding of a fragment's shape masks (SPEC.md 7): binary (frame,
// camera) masks in atlas space, context-adaptive binary arithmetic coding with
// a spatial template plus the co-located texels of the same camera's mask in
// the previous frame, and "typical prediction" rows (a row equal to its
// reference costs one decision).
#ifndef FVV_CODEC_MASK_CODER_H_
#define FVV_CODEC_MASK_CODER_H_

#include <cstdint>
#include <vector>

#include "codec/block.h"
#include "codec/status.h"

namespace fvv {

// masks: shape.size() bytes, 0 or 1, in (t, c, y, x) order, x fastest.
std::vector<uint8_t> EncodeMasks(const uint8_t* masks, const Shape4D& shape);
// Decodes exactly shape.size() texels into `out`; Corrupt/Truncated when the data
// ends early.
Status DecodeMasks(const uint8_t* data, size_t size, const Shape4D& shape, uint8_t* out);

}  // namespace fvv

#endif  // FVV_CODEC_MASK_CODER_H_
