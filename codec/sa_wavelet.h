// The shape-adaptive 2D wavelet transform: only the
// samples inside a shape are transformed, and the transform yields exactly as
// many coefficients as there are samples, placed where a shape mask of each
// subband says (the decoder derives the same masks from the shape alone).
//
// Each row (then each column) is cut into runs of in-shape samples; every run
// is lifted on its own as a signal of its length (even samples to the low
// band, odd to the high band, symmetric extension at the run's ends), and a
// run starting at position s puts its low coefficients from floor(s / 2) in
// the low half and its high ones from floor(s / 2) in the high half. Runs are
// separated by at least one out-of-shape sample, so their coefficients never
// collide. Levels go on in the low-low band (Mallat layout). A one-sample run
// passes through as a low coefficient. With the reversible kernels the
// inverse is exact.
#ifndef FVV_CODEC_SA_WAVELET_H_
#define FVV_CODEC_SA_WAVELET_H_

#include <cstdint>
#include <vector>

#include "codec/wavelet.h"

namespace fvv {

// A plane of width x height samples, row-major, with its shape (1 = inside).
struct ShapePlane {
  uint32_t width = 0, height = 0;
  std::vector<int32_t> samples;
  std::vector<uint8_t> mask;
};

// The masks of every stage of `levels` levels: [2l] before level l's row
// transform, [2l + 1] before its column transform; [2 * levels] the final
// layout (where the coefficients are). Each covers the whole plane.
std::vector<std::vector<uint8_t>> ShapeAdaptiveMasks(const std::vector<uint8_t>& mask,
                                                     uint32_t width, uint32_t height, int levels);

// The number of levels the coder uses for a plane: halving the shorter side
// down to about 4 samples, at most 6.
int ShapeAdaptiveLevels(uint32_t width, uint32_t height);

// In place: samples outside the shape are ignored and come out 0; the plane's
// mask becomes the coefficients' layout.
void ForwardShapeAdaptive(WaveletKernel kernel, int levels, ShapePlane* plane);
// The inverse, given the plane in coefficient layout and the original shape
// mask (`shape`); restores the mask to `shape`.
void InverseShapeAdaptive(WaveletKernel kernel, int levels, const std::vector<uint8_t>& shape,
                          ShapePlane* plane);
// The same with the stage masks already derived (ShapeAdaptiveMasks(shape)).
void InverseShapeAdaptive(WaveletKernel kernel, int levels,
                          const std::vector<std::vector<uint8_t>>& stage_masks, ShapePlane* plane);

}  // namespace fvv

#endif  // FVV_CODEC_SA_WAVELET_H_
