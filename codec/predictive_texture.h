// The predictive multi-view texture scheme, on one GOP of
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

#include "codec/base/parallel.h"
#include "codec/base/status.h"
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
  int levels = 0;  // ShapeAdaptiveLevels(width, height)
  ChannelStreams t00;
  std::vector<ChannelStreams> r0;  // per frame
  std::vector<ChannelStreams> r;   // per (t, c)
  uint64_t Bytes() const;
  // Every stream in the bitstream's order (SPEC.md 9.8): T00 Y, U, V; R0(t)
  // Y, U, V for t = 0..; R(t, c) Y, U, V for t = 0.., c = 0...
  std::vector<const std::vector<uint8_t>*> Ordered() const;
  std::vector<std::vector<uint8_t>*> Ordered();
  // Empty streams of the right count for a GOP of `frames` x `cameras`.
  void Resize(uint32_t frames, uint32_t cameras);
};

struct PredictiveEncodeOptions {
  WaveletKernel kernel = WaveletKernel::kLeGall53;
  // Rate: a byte target for all streams together, else a PSNR target
  // (channel-weighted YUV over the seen texels, as the SPIHT coder's), else
  // every stream whole (lossless in YUV with the reversible kernels).
  uint64_t target_bytes = 0;
  double target_psnr = 0;
  std::array<double, 3> channel_weights{1.0, 1.0861, 0.8252};
  ParallelRunner runner = SerialRunner;
};

// The decoded GOP: per (t, c) RGB (0 where unseen), and the decoded
// references it was built from (YUV planes, width * height each; each signal
// is 0 outside its support).
struct PredictiveDecoded {
  std::vector<uint8_t> rgb;                             // (t, c, y, x, 3)
  std::array<std::vector<int32_t>, 3> t00;              // decoded T00 + 128
  std::vector<std::array<std::vector<int32_t>, 3>> r0;  // decoded R0(t)
  std::vector<std::array<std::vector<int32_t>, 3>> r;   // decoded R(t, c)
  // Per (t, c), every texel: clamp(T00 + R0 + R, 0, 255), the output samples
  // (outside the camera's mask they carry no information).
  std::vector<std::array<std::vector<int32_t>, 3>> yuv;
};

struct PredictiveDecodeOptions {
  // Bytes for all streams together; 0 = whole. Stream s of size S_s keeps its
  // first floor(S_s * max_bytes / S) bytes (S: all streams), SPEC.md B.2.
  uint64_t max_bytes = 0;
  ParallelRunner runner = SerialRunner;
};

StatusOr<PredictiveStreams> EncodePredictive(const PredictiveGop& gop,
                                             const PredictiveEncodeOptions& options,
                                             PredictiveDecoded* reconstruction = nullptr);

// Decodes streams made for `gop`'s shape and masks (rgb unused). Streams may
// be cut (any prefix of each decodes); any bytes decode safely. Fills out->rgb
// only when `want_rgb`.
Status DecodePredictive(const PredictiveStreams& streams, const PredictiveGop& gop,
                        PredictiveDecoded* out,
                        const PredictiveDecodeOptions& options = PredictiveDecodeOptions(),
                        bool want_rgb = true);

}  // namespace fvv

#endif  // FVV_CODEC_PREDICTIVE_TEXTURE_H_
