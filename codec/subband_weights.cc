#include "codec/subband_weights.h"

#include <algorithm>
#include <cmath>

namespace fvv {
namespace {

// round(65536 * norm); index = splits (low) or k - 1 (high). See ComputeAxisNorm.
constexpr uint32_t kLowNorm[3][kMaxLevelsPerAxis + 1] = {
    {65536, 92682, 131072, 185364, 262144, 370728, 524288},  // Haar
    {65536, 80265, 108679, 151939, 214249, 302772, 428105},  // 5/3
    {65536, 74696, 87927, 102130, 117764, 135490, 155791},   // 9/7
};
constexpr uint32_t kHighNorm[3][kMaxLevelsPerAxis] = {
    {46341, 65536, 92682, 131072, 185364, 262144},
    {55561, 62924, 82532, 114322, 160817, 227125},
    {58149, 64453, 76819, 89806, 103755, 119433},
};

bool Reversible(WaveletKernel k) { return k != WaveletKernel::kCdf97; }

}  // namespace

uint32_t AxisLowNormQ16(WaveletKernel kernel, int splits) {
  return kLowNorm[static_cast<int>(kernel)][splits];
}
uint32_t AxisHighNormQ16(WaveletKernel kernel, int k) {
  return kHighNorm[static_cast<int>(kernel)][k - 1];
}

int DefaultFracBits(WaveletKernel kernel) { return Reversible(kernel) ? 0 : kFracBits97; }

double ComputeAxisNorm(WaveletKernel kernel, bool high, int level) {
  // An impulse in the middle of the band of a long signal, synthesised to the
  // sample domain; the middle keeps boundary extension out of the measurement.
  const uint32_t n = 4096;
  std::array<uint32_t, kMaxLevelsPerAxis + 1> lo{};
  lo[0] = n;
  for (int k = 1; k <= kMaxLevelsPerAxis; ++k) lo[k] = (lo[k - 1] + 1) / 2;
  std::vector<double> x(n, 0.0);
  x[high ? (lo[level] + lo[level - 1]) / 2 : lo[level] / 2] = 1.0;
  for (int l = level; l >= 1; --l) LiftInverseReal(kernel, lo[l - 1], x.data());
  double energy = 0;
  for (double v : x) energy += v * v;
  return std::sqrt(energy);
}

uint32_t AxisNormQ16(WaveletKernel kernel, BandWeights weights, const AxisGeometry& axis, int code,
                     int level) {
  if (weights == BandWeights::kOwnBand && level <= kMaxLevelsPerAxis) {
    return code == level ? AxisHighNormQ16(kernel, level)
                         : AxisLowNormQ16(kernel, std::min(level, axis.levels));
  }
  return code == 0 ? AxisLowNormQ16(kernel, axis.levels) : AxisHighNormQ16(kernel, code);
}

SubbandQuantisers::SubbandQuantisers(WaveletKernel kernel, int frac, BandWeights weights,
                                     const WaveletGeometry& g)
    : bands_(kBandIds) {
  // Reversible kernels: weights relative to the finest all-detail band, as powers of two.
  uint64_t ref = 1u << 16;
  for (int a = 0; a < kAxes; ++a)
    if (g.axis[a].levels >= 1) ref = (ref * AxisHighNormQ16(kernel, 1) + 32768) >> 16;
  for (int id = 0; id < kBandIds; ++id) {
    std::array<uint8_t, kAxes> codes;
    int rest = id;
    bool valid = true;
    for (int a = kAxes - 1; a >= 0; --a) {
      codes[a] = static_cast<uint8_t>(rest % kBandCodes);
      rest /= kBandCodes;
      if (codes[a] > g.axis[a].levels) valid = false;
    }
    if (!valid) continue;
    uint64_t w = 1u << 16;  // Q16 product of the axis norms
    const int level = BandLevel(codes);
    for (int a = 0; a < kAxes; ++a) {
      const uint32_t axis_norm = AxisNormQ16(kernel, weights, g.axis[a], codes[a], level);
      w = (w * axis_norm + 32768) >> 16;
    }
    BandQuantiser& q = bands_[id];
    if (Reversible(kernel)) {
      // shift = round(log2(w / ref)), using sqrt(2) in Q16 (92682) as the rounding threshold.
      int shift = 0;
      while (shift < 15 && ((w << 16) >= ((ref * 92682) << shift))) ++shift;
      q.mul_q16 = 1u << (16 + shift);
      q.inv_q16 = 1u << (16 - shift);
      const double ratio =
          static_cast<double>(w) / static_cast<double>(uint64_t{1} << (16 + shift));
      q.distortion = ratio * ratio;
    } else {
      q.mul_q16 = static_cast<uint32_t>(w);
      q.inv_q16 = static_cast<uint32_t>(((uint64_t{1} << 32) + w / 2) / w);
      q.distortion = 1.0;
    }
    q.distortion /= static_cast<double>(1u << (2 * frac));
  }
}

}  // namespace fvv
