// Filling of unused texels before the transform (encoder side only).
//
// A 4D mean pyramid is built down to 1x1x1x1: each level halves every axis
// (rounding up; an axis of size 1 stays 1) and a parent is the rounded mean of its
// *used* children, used if any child is. Walking back up, every unused texel
// takes its parent's (final) value. Used texels never change. The result is a
// smooth continuation of the content into the holes, so the wavelet transform
// spends almost no bits on texels no camera saw.
#ifndef FVV_CODEC_FILL_H_
#define FVV_CODEC_FILL_H_

#include "codec/block.h"

namespace fvv {

// mask.size() must equal plane->shape.count(). A plane with no used texel is
// filled with fill_value.
void FillUnused(const UsedMask& mask, int32_t fill_value, Plane4D* plane);

// The chroma-resolution mask for 4:2:0: a chroma texel is used if any of its luma
// texels is.
UsedMask DownsampleMask(const UsedMask& mask, const Shape4D& luma, const Shape4D& chroma);

}  // namespace fvv

#endif  // FVV_CODEC_FILL_H_
