// Filling of unused texels before the transform (encoder side only).
//
// A 4D mean pyramid is built down to 1x1x1x1: each level halves every axis
// (rounding up; an axis of size 1 stays 1) and a parent is the rounded mean of its
// *used* children, used if any child is. Walking back up, every unused texel
// takes its parent's (final) value, or (kBilinear) interpolates its nearest
// parents. Used texels never change. The result continues the content into the
// holes, so the wavelet transform spends few bits on texels no camera saw; a
// sparse-fill refinement (SparseFill) then removes most of what it still costs.
#ifndef FVV_CODEC_FILL_H_
#define FVV_CODEC_FILL_H_

#include "codec/base/parallel.h"
#include "codec/block.h"
#include "codec/wavelet.h"

namespace fvv {

// How the walk back up fills an unused texel: kParent takes its parent's value
// (the original system's fill: flat within each dyadic cell, with steps between
// cells that the 9/7 pays for along every hole's edge); kBilinear interpolates
// the four nearest parents in y and x (push-pull), a smooth continuation that
// the 9/7 codes cheaper (docs/encoder.md, "Filling texels no camera saw").
enum class FillPull : uint8_t { kParent, kBilinear };

// mask.size() must equal plane->shape.count(). A plane with no used texel is
// filled with fill_value.
void FillUnused(const UsedMask& mask, int32_t fill_value, Plane4D* plane,
                FillPull pull = FillPull::kParent);

// How a SPIHT encoder fills unused texels: FillUnused with `pull`, then
// `iterations` sparse-fill projections (below).
struct FillOptions {
  FillPull pull = FillPull::kBilinear;
  int iterations = 3;  // 0: the pyramid fill is left as it is
  double start = 32;   // first threshold, in steps of the 8-bit scale
  double end = 4;      // last threshold
};

// Sparse fill: refines a filled plane so that the wavelet transform that
// follows needs as few significant coefficients as the used texels allow.
// Alternating projections: transform, zero every coefficient whose
// image-domain magnitude (coefficient times its synthesis norm) is below a
// threshold, transform back, put the used texels back and clamp to the
// channel's range; the threshold falls geometrically from `start` to `end`
// (steps of the 8-bit scale) over the iterations. Used texels never change.
void SparseFill(WaveletKernel kernel, const UsedMask& mask, const SampleRange& range,
                const FillOptions& options, const ParallelRunner& runner, Plane4D* plane);

// The chroma-resolution mask for 4:2:0: a chroma texel is used if any of its luma
// texels is.
UsedMask DownsampleMask(const UsedMask& mask, const Shape4D& luma, const Shape4D& chroma);

}  // namespace fvv

#endif  // FVV_CODEC_FILL_H_
