// Shape-adaptive BISK (binary set splitting with k-d trees): an embedded coder of the in-shape
// coefficients of a shape-adaptive wavelet transform (codec/sa_wavelet.h). Only texels inside the
// shape cost anything.
//
// Sets are rectangles of coefficients, each shrunk to the bounding box of the
// in-shape coefficients it holds (the decoder knows the shape, so it shrinks
// alike; empty sets vanish). The list of insignificant sets starts with the
// subbands, coarsest first. Coefficients are scaled by whole bits per subband
// first (an orthonormal transform's relative weights), so each bitplane
// lowers the squared error about evenly. Per bitplane n, from the top:
// - sorting: each listed set is tested (max |c| >= 2^n); a significant set
//   splits into two halves, alternately across x and across y, each tested in
//   turn (the second without a bit when the first was insignificant: one of
//   them must be significant), down to single coefficients, which send their
//   sign and join the significant list;
// - refinement: coefficients significant before this plane send bit n.
// Every decision goes through the adaptive binary range coder with contexts:
// set significance by the set's size, coefficient significance by subband
// level and whether a neighbour is significant, sign, and refinement (first
// or later). Any prefix of the stream decodes (codec/range_coder.h's
// truncation rule) to the coefficients known so far, reconstructed at the
// middle of their uncertainty interval.
//
// Stream: 1 byte, the top bitplane (0..30), or 255 for a plane of zeros; then
// the range coder's bytes.
#ifndef FVV_CODEC_BISK_H_
#define FVV_CODEC_BISK_H_

#include <cstddef>
#include <cstdint>
#include <vector>

#include "codec/base/status.h"
#include "codec/sa_wavelet.h"

namespace fvv {

// Transforms `image` (samples inside its mask) with `levels` levels of the
// shape-adaptive transform and codes every bitplane. `plane_ends` (may be
// null) receives, per bitplane from the top, the stream bytes a decoder needs
// to complete it: the truncation points rate control cuts at.
std::vector<uint8_t> BiskEncode(const ShapePlane& image, WaveletKernel kernel, int levels,
                                std::vector<size_t>* plane_ends = nullptr);

struct BiskDecodeInfo {
  int planes_completed = 0;  // whole bitplanes decoded (sorting and refinement)
  bool truncated = false;    // the bytes ran out before the last plane
};

// Decodes `size` bytes (any prefix of a BiskEncode stream) into `image`, whose
// width, height and mask (the shape) must be set; samples outside the shape
// are 0. Corrupt only when the header is impossible. Any input is safe:
// arithmetic wraps as the inverse transform defines, and nothing overflows.
// `stage_masks` (may be null) are ShapeAdaptiveMasks(shape, ...), for callers
// that decode several signals over one shape.
Status BiskDecode(const uint8_t* data, size_t size, WaveletKernel kernel, int levels,
                  ShapePlane* image, BiskDecodeInfo* info = nullptr,
                  const std::vector<std::vector<uint8_t>>* stage_masks = nullptr);

}  // namespace fvv

#endif  // FVV_CODEC_BISK_H_
