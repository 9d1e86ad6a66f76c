// What encoder and decoder of a block share: parameter validation and error
// statistics.
#include <algorithm>
#include <cmath>

#include "codec/block_codec.h"

namespace fvv {
namespace {

constexpr uint32_t kMaxAxisSize = 65535;
constexpr uint64_t kMaxSamples = uint64_t{1} << 30;  // indices keep a spare bit in SPIHT lists

}  // namespace

double ChannelMse(const Plane4D& a, const Plane4D& b, const UsedMask* mask, int sample_frac) {
  double sum = 0;
  size_t count = 0;
  for (size_t i = 0; i < a.samples.size(); ++i) {
    if (mask && !(*mask)[i]) continue;
    const double d = a.samples[i] - b.samples[i];
    sum += d * d;
    ++count;
  }
  return count ? sum / static_cast<double>(count) / static_cast<double>(1 << (2 * sample_frac))
               : 0.0;
}

int UsableSampleFrac(WaveletKernel kernel, int frac_bits_97, BandWeights weights, int requested) {
  if (kernel != WaveletKernel::kCdf97 || weights != BandWeights::kOwnBand) return 0;
  return std::clamp(requested, 0, std::min(kMaxSampleFrac, frac_bits_97));
}

double PsnrFromMse(double mse) {
  if (mse <= 1e-10) return 99.0;
  return std::min(99.0, 10.0 * std::log10(255.0 * 255.0 / mse));
}

Status ValidateParams(const BlockParams& p) {
  for (int a = 0; a < kAxes; ++a) {
    if (p.shape.n[a] < 1 || p.shape.n[a] > kMaxAxisSize)
      return LimitExceeded("block axis " + std::to_string(a) + " has size " +
                           std::to_string(p.shape.n[a]) + " (allowed 1.." +
                           std::to_string(kMaxAxisSize) + ")");
  }
  if (p.shape.count() > kMaxSamples)
    return LimitExceeded("block of " + p.shape.ToString() + " has more than 2^30 samples");
  if (static_cast<int>(p.kernel) > 2)
    return Corrupt("unknown wavelet kernel " + std::to_string(static_cast<int>(p.kernel)));
  if (p.kernel == WaveletKernel::kCdf97 ? !ValidFracBits97(p.frac_bits) : p.frac_bits != 0)
    return Corrupt("sample precision of " + std::to_string(p.frac_bits) +
                   " fractional bits for the " + KernelName(p.kernel) + " kernel (allowed: " +
                   (p.kernel == WaveletKernel::kCdf97
                        ? std::to_string(kMinFracBits97) + ".." + std::to_string(kMaxFracBits97)
                        : std::string("0")) +
                   ")");
  if (static_cast<int>(p.coder) >= kEntropyCoders)
    return Corrupt("unknown entropy coder " + std::to_string(static_cast<int>(p.coder)));
  if (static_cast<int>(p.colour) > 1)
    return Corrupt("unknown colour space " + std::to_string(static_cast<int>(p.colour)));
  if (static_cast<int>(p.chroma) > 1)
    return Corrupt("unknown chroma format " + std::to_string(static_cast<int>(p.chroma)));
  if (p.sample_frac > std::min<int>(kMaxSampleFrac, p.frac_bits))
    return Corrupt("decoded samples with " + std::to_string(p.sample_frac) +
                   " fractional bits from a transform with " + std::to_string(p.frac_bits) +
                   " (allowed: 0.." + std::to_string(std::min<int>(kMaxSampleFrac, p.frac_bits)) +
                   ")");
  if (p.sample_frac > 0 && p.colour == ColourSpace::kRct)
    return Corrupt("RCT (lossless) samples with " + std::to_string(p.sample_frac) +
                   " fractional bits (RCT takes whole samples)");
  return Status::Ok();
}

}  // namespace fvv
