// What the predictive scheme's encoder and decoder share (codec-internal).
#ifndef FVV_CODEC_PREDICTIVE_TEXTURE_COMMON_H_
#define FVV_CODEC_PREDICTIVE_TEXTURE_COMMON_H_

#include <algorithm>
#include <cstdint>
#include <vector>

#include "codec/predictive_texture.h"

namespace fvv {

// T00 is coded level-shifted (YCbCr samples are 0..255 around 128).
constexpr int32_t kPredictiveLevelShift = 128;
// Every decoded signal is clamped into this range, so that sums of decoded
// signals stay far inside int32 whatever a (corrupt) stream holds; valid
// signals never come near it.
constexpr int32_t kPredictiveSignalMin = -32768, kPredictiveSignalMax = 32767;

// The output sample: decoded T00 (level shift included) + R0(t) + R(t, c),
// clamped to the 8-bit range.
inline int32_t PredictiveSample(int32_t t00, int32_t r0, int32_t r) {
  return std::clamp(t00 + r0 + r, 0, 255);
}

// A shape and the masks of its transform stages (ShapeAdaptiveMasks).
struct SignalShape {
  std::vector<uint8_t> mask;
  std::vector<std::vector<uint8_t>> stages;
};
SignalShape MakeSignalShape(std::vector<uint8_t> mask, uint32_t width, uint32_t height, int levels);

// The supports: texels some camera of some frame saw, and per frame those
// some camera saw then.
struct PredictiveSupports {
  std::vector<uint8_t> all;
  std::vector<std::vector<uint8_t>> frame;
};
PredictiveSupports MakeSupports(const PredictiveGop& gop);

// One BISK stream (its first `size` bytes) decoded over `shape`, clamped to
// the signal range (the first error lands in *status).
std::vector<int32_t> DecodeSignal(const uint8_t* data, size_t size, WaveletKernel kernel,
                                  int levels, uint32_t width, uint32_t height,
                                  const SignalShape& shape, Status* status);

// out->rgb from out->yuv over the GOP's masks.
void AssembleRgb(const PredictiveGop& gop, PredictiveDecoded* out);

}  // namespace fvv

#endif  // FVV_CODEC_PREDICTIVE_TEXTURE_COMMON_H_
