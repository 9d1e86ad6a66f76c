// The separable 4D wavelet transform and its geometry.
//
// Geometry: axis a of size n is split K_a = min(6, ceil(log2 n)) times; each split
// halves the current low band (low part rounded up). Global level l = 1..L,
// L = max K_a, splits every axis with l <= K_a ("finest first"), so short axes
// (8 frames, 8 cameras) are exhausted after the first levels while the spatial
// axes go on. In the Mallat layout along one axis the final low band is
// [0, lo[K]) and the detail of split k is [lo[k], lo[k-1]).
//
// Kernels run as integer lifting on deinterleaved samples with whole-sample
// symmetric extension; the 9/7 lifting constants are Q16 and its normalising
// scale is left out (subband weights take its place), so every kernel maps
// integers to integers and the inverse is exact and platform-independent.
#ifndef FVV_CODEC_WAVELET_H_
#define FVV_CODEC_WAVELET_H_

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "codec/base/parallel.h"
#include "codec/block.h"

namespace fvv {

enum class WaveletKernel : uint8_t {
  kHaar = 0,      // reversible S-transform (the original system's kernel)
  kLeGall53 = 1,  // reversible 5/3 of JPEG 2000
  kCdf97 = 2,     // 9/7 of JPEG 2000, Q16 fixed-point lifting
};
const char* KernelName(WaveletKernel k);

constexpr int kMaxLevelsPerAxis = 6;

struct AxisGeometry {
  uint32_t n = 1;
  int levels = 0;                                    // K_a
  std::array<uint32_t, kMaxLevelsPerAxis + 1> lo{};  // lo[0] = n, lo[k] = ceil(lo[k-1] / 2)
  std::vector<uint8_t> band;  // per position: 0 = final low band, k = detail of split k

  uint32_t LowExtentAfter(int splits) const { return lo[splits < levels ? splits : levels]; }
};

struct WaveletGeometry {
  Shape4D shape;
  std::array<AxisGeometry, kAxes> axis;
  int levels = 0;  // L

  explicit WaveletGeometry(const Shape4D& shape);
  WaveletGeometry() = default;
  // Extent of the low region R(l) along axis a (R(0) is the whole block).
  uint32_t RegionExtent(int axis_index, int l) const { return axis[axis_index].LowExtentAfter(l); }
  bool AxisSplitAt(int axis_index, int l) const { return l >= 1 && l <= axis[axis_index].levels; }
};

// Forward and inverse transforms, in place on one plane of the block. Callers
// level-shift (and for the 9/7 scale by 2^f, subband_weights.h) around them.
void ForwardTransform4D(WaveletKernel kernel, const WaveletGeometry& geometry,
                        const ParallelRunner& runner, int32_t* data);
// `finish(begin, end)`, when given, is called (possibly from the runner's
// threads) on disjoint sample ranges that together cover the block, each once
// its samples are final: while a plane is still in cache where the transform
// works plane by plane, at the end otherwise.
void InverseTransform4D(WaveletKernel kernel, const WaveletGeometry& geometry,
                        const ParallelRunner& runner, int32_t* data,
                        const std::function<void(size_t, size_t)>& finish = nullptr);

// 1D lifting on m rows of v elements each, deinterleaved: rows [0, ceil(m/2)) are
// the even samples (become low band), the rest the odd ones (become high band).
void LiftForward(WaveletKernel kernel, uint32_t m, uint32_t v, int32_t* rows);
void LiftInverse(WaveletKernel kernel, uint32_t m, uint32_t v, int32_t* rows);

// The same lifting in double precision without rounding; used to derive the
// subband weights (synthesis basis norms) and by tests.
void LiftInverseReal(WaveletKernel kernel, uint32_t m, double* rows);

}  // namespace fvv

#endif  // FVV_CODEC_WAVELET_H_
