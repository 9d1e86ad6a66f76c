// Subband weighting: coefficients are scaled by the L2 norm of their synthesis
// basis function before bitplane coding, so that one unit of error in any
// subband costs the same image-domain squared error. SPIHT's bitplane order is
// then also rate-distortion order.
//
// The 4D norm is the product of per-axis 1D norms (the transform is separable).
// The 1D norms are pinned below as Q16 integers (derived by
// ComputeAxisNorm from the real-valued lifting; a test recomputes them), and the
// 4D product is formed in integers, so encoder and decoder agree bit for bit.
//
// Reversible kernels (Haar, 5/3) round each weight to a power of two so the
// scaling is a shift and full-rate coding stays lossless; the 9/7 uses exact
// weights, and its samples carry f fractional bits (SPEC.md 9.6).
#ifndef FVV_CODEC_SUBBAND_WEIGHTS_H_
#define FVV_CODEC_SUBBAND_WEIGHTS_H_

#include <array>
#include <cstdint>
#include <vector>

#include "codec/wavelet.h"

namespace fvv {

// Per-axis band code as in AxisGeometry::band: 0 = final low band, k = detail of split k.
// Number of distinct 4D bands: 7^4.
constexpr int kBandCodes = kMaxLevelsPerAxis + 1;
constexpr int kBandIds = kBandCodes * kBandCodes * kBandCodes * kBandCodes;

// How a coefficient's weight is formed from the per-axis norms (SPEC.md 9.3).
enum class BandWeights : uint8_t {
  // Format versions 1 to 5: each axis contributes the norm of the band its
  // position lies in along that axis. That is the true norm only where every
  // axis was split at the coefficient's level: in the Mallat layout a level-1
  // detail band such as (y low, x high) spans every y band code of the low part,
  // and the weights of its coefficients ranged from 0.86 to 2.1 times the
  // synthesis norm (1.01), so SPIHT's bitplanes were not in rate-distortion order.
  kAxisBands = 0,
  // Format version 6 (coding tool 15): the norm of the coefficient's own band. At
  // its level l (the smallest non-zero band code; roots have none), an axis whose
  // band code is l contributes the detail norm of split l, every other axis the
  // low norm after min(l, K_a) splits (docs/encoder.md, "Own-band subband
  // weights").
  kOwnBand = 1,
};

// Q16 1D synthesis norm of the low band after `splits` splits, or of the detail
// band of split k.
uint32_t AxisLowNormQ16(WaveletKernel kernel, int splits);
uint32_t AxisHighNormQ16(WaveletKernel kernel, int k);
// A coefficient's level from its per-axis band codes: the smallest non-zero
// code (the split that made it a detail coefficient), or kMaxLevelsPerAxis + 1
// for the final low band.
inline int BandLevel(const std::array<uint8_t, kAxes>& codes) {
  int level = kMaxLevelsPerAxis + 1;
  for (uint8_t c : codes)
    if (c != 0 && c < level) level = c;
  return level;
}
// The Q16 norm axis `axis` contributes to the weight of a coefficient with band
// code `code` on that axis and level `level` (BandLevel).
uint32_t AxisNormQ16(WaveletKernel kernel, BandWeights weights, const AxisGeometry& axis, int code,
                     int level);
// The same from first principles, in double (for tests and the spec's table).
double ComputeAxisNorm(WaveletKernel kernel, bool high, int level);

// Fractional bits of sample precision the transform input carries (samples <<
// f, SPEC.md 9.6's f). The reversible kernels have none. The 9/7 had 2 up to
// format version 2 (texr version 0); format version 3 declares f in texr
// version 1, and the encoder writes 5: at 2 bits the rounding of the lifting
// steps cost as much as the quantiser at high rates (docs/encoder.md, "The
// 9/7's sample precision"). Above 6 nothing is gained and the headroom of 32-bit
// coefficients shrinks.
constexpr int kFracBits97Legacy = 2;
constexpr int kFracBits97 = 5;
constexpr int kMinFracBits97 = 2;
constexpr int kMaxFracBits97 = 6;
// What the encoder writes for a kernel: 0, or kFracBits97 for the 9/7.
int DefaultFracBits(WaveletKernel kernel);
// A kernel's f given the 9/7 precision setting: 0 for the reversible kernels.
inline int KernelFracBits(WaveletKernel kernel, int frac_bits_97) {
  return kernel == WaveletKernel::kCdf97 ? frac_bits_97 : 0;
}
// f of payloads that predate the precision field ('texr' version 0, block file
// version 1).
inline int LegacyFracBits(WaveletKernel kernel) {
  return KernelFracBits(kernel, kFracBits97Legacy);
}
inline bool ValidFracBits97(int f) { return f >= kMinFracBits97 && f <= kMaxFracBits97; }

struct BandQuantiser {
  uint32_t mul_q16 = 1u << 16;  // v = round(c * mul / 2^16)
  uint32_t inv_q16 = 1u << 16;  // c = round(v * inv / 2^16)
  double distortion = 1.0;      // image-domain squared error per unit^2 of v (encoder only)
};

class SubbandQuantisers {
 public:
  SubbandQuantisers(WaveletKernel kernel, int frac_bits, BandWeights weights,
                    const WaveletGeometry& geometry);
  // Band id of a coefficient from its per-axis band codes.
  static int BandId(const std::array<uint8_t, kAxes>& codes) {
    return ((codes[0] * kBandCodes + codes[1]) * kBandCodes + codes[2]) * kBandCodes + codes[3];
  }
  const BandQuantiser& operator[](int band_id) const { return bands_[band_id]; }

 private:
  std::vector<BandQuantiser> bands_;
};

// Sign-symmetric quantise / dequantise with the Q16 factors.
inline int32_t QuantiseCoefficient(int32_t c, uint32_t mul_q16) {
  const uint64_t m = (static_cast<uint64_t>(c < 0 ? -int64_t{c} : c) * mul_q16 + 32768) >> 16;
  const int32_t v = static_cast<int32_t>(m > 0x3FFFFFFF ? 0x3FFFFFFF : m);
  return c < 0 ? -v : v;
}
inline int32_t DequantiseMagnitude(uint32_t mag, uint32_t inv_q16) {
  const uint64_t c = (uint64_t{mag} * inv_q16 + 32768) >> 16;
  return static_cast<int32_t>(c > 0x3FFFFFFF ? 0x3FFFFFFF : c);
}

}  // namespace fvv

#endif  // FVV_CODEC_SUBBAND_WEIGHTS_H_
