// The predictive multi-view texture scheme (issue 9, section 1), on one GOP of
// frames x cameras atlas textures with their visibility masks, in YUV (BT.601):
//
//   T0(t)  = visibility-weighted mean over the cameras of frame t
//   T00    = mean of the T0(t) over the GOP's frames (texels weighted by how
//            often they were seen)
//   R0(t)  = T0(t) - decoded T00
//   R(t,c) = texture(t, c) - (decoded T00 + decoded R0(t))
//
// Each of these is coded with shape-adaptive BISK (codec/bisk.h) over its own
// support: T00 over every texel some camera of some frame saw, R0(t) over
// those seen at frame t, R(t, c) over camera c's mask. Differences are taken
// against the decoded references (closed loop), so coding error does not
// accumulate, and a decoder reaches any texture with two additions:
// decoded T00 + decoded R0(t) + decoded R(t, c). The GOP is the span of T00
// (several per sequence; its length is the GOP's frame count).
//
// Rate: every stream is cut at the same bitplane threshold tau (planes above
// it whole, the one at it in proportion), which spends bits where they lower
// the error most evenly; the encoder searches tau for a byte target.
#ifndef FVV_CODEC_PREDICTIVE_TEXTURE_H_
#define FVV_CODEC_PREDICTIVE_TEXTURE_H_

#include <array>
#include <cstdint>
#include <vector>

#include "codec/status.h"
#include "codec/wavelet.h"

namespace fvv {

struct PredictiveGop {
  uint32_t frames = 0, cameras = 0, width = 0, height = 0;
  std::vector<uint8_t> rgb;   // (t, c, y, x, 3)
  std::vector<uint8_t> mask;  // (t, c, y, x), 1 = seen
};

using ChannelStreams = std::array<std::vector<uint8_t>, 3>;  // Y, U, V (BISK streams)

struct PredictiveStreams {
  WaveletKernel kernel = WaveletKernel::kLeGall53;
  int levels = 0;
  ChannelStreams t00;
  std::vector<ChannelStreams> r0;  // per frame
  std::vector<ChannelStreams> r;   // per (t, c)
  uint64_t Bytes() const;
};

struct PredictiveEncodeOptions {
  WaveletKernel kernel = WaveletKernel::kLeGall53;
  uint64_t target_bytes = 0;  // 0: every stream whole (lossless with reversible kernels)
};

// The decoded GOP: per (t, c) RGB (0 where unseen), and the decoded
// references it was built from (YUV planes, width * height each).
struct PredictiveDecoded {
  std::vector<uint8_t> rgb;                              // (t, c, y, x, 3)
  std::array<std::vector<int32_t>, 3> t00;               // decoded T00
  std::vector<std::array<std::vector<int32_t>, 3>> r0;   // decoded R0(t)
  std::vector<std::array<std::vector<int32_t>, 3>> r;    // decoded R(t, c)
  std::vector<std::array<std::vector<int32_t>, 3>> yuv;  // per (t, c): T00 + R0 + R
};

StatusOr<PredictiveStreams> EncodePredictive(const PredictiveGop& gop,
                                             const PredictiveEncodeOptions& options,
                                             PredictiveDecoded* reconstruction = nullptr);

// Decodes streams made for `gop`'s shape and masks (rgb unused). Streams may
// be cut (any prefix of each decodes).
Status DecodePredictive(const PredictiveStreams& streams, const PredictiveGop& gop,
                        PredictiveDecoded* out);

}  // namespace fvv

#endif  // FVV_CODEC_PREDICTIVE_TEXTURE_H_
