// What the predictive scheme's encoder and decoder share (codec-internal).
#ifndef FVV_CODEC_PREDICTIVE_TEXTURE_SUPPORT_H_
#define FVV_CODEC_PREDICTIVE_TEXTURE_SUPPORT_H_

#include <cstdint>
#include <vector>

#include "codec/predictive_texture.h"

namespace fvv {

// T00 is coded level-shifted (YCbCr samples are 0..255 around 128).
constexpr int32_t kPredictiveLevelShift = 128;

// The supports: texels some camera of some frame saw, and per frame those
// some camera saw then.
struct PredictiveSupports {
  std::vector<uint8_t> all;
  std::vector<std::vector<uint8_t>> frame;
};
PredictiveSupports MakeSupports(const PredictiveGop& gop);

// One BISK stream decoded over `shape` (the first error lands in *status).
std::vector<int32_t> DecodeSignal(const std::vector<uint8_t>& stream, WaveletKernel kernel,
                                  int levels, uint32_t width, uint32_t height,
                                  const std::vector<uint8_t>& shape, Status* status);

// out->rgb from out->yuv over the GOP's masks.
void AssembleRgb(const PredictiveGop& gop, PredictiveDecoded* out);

}  // namespace fvv

#endif  // FVV_CODEC_PREDICTIVE_TEXTURE_SUPPORT_H_
