// 4D SPIHT encoder and decoder of one channel's quantised wavelet coefficients.
#ifndef FVV_CODEC_SPIHT4D_H_
#define FVV_CODEC_SPIHT4D_H_

#include <chrono>
#include <cstdint>
#include <vector>

#include "codec/base/status.h"
#include "codec/spiht4d_common.h"

namespace fvv {

struct SpihtEncoded {
  uint8_t planes = 0;  // bitplanes coded: n_max + 1 (0 when every coefficient is zero)
  std::vector<uint8_t> data;
  std::vector<TruncationPoint> points;
  // Rate-distortion curve of the stream, for rate allocation: bytes at each pass
  // end and the estimated image-domain squared error there (sum over samples).
  std::vector<uint64_t> rd_bytes;
  std::vector<double> rd_distortion;  // rd_distortion[0] is the error of decoding nothing
};

// Encodes until the stream is complete or a decoder would need more than
// max_bytes; in the second case the stream is cut to max_bytes so that decoders
// never see a decision that was not encoded.
SpihtEncoded SpihtEncode(const SpihtTree& tree, const SubbandQuantisers& quantisers,
                         const std::vector<int32_t>& coefficients, EntropyCoder coder,
                         uint64_t max_bytes);

struct SpihtDecodeLimits {
  uint64_t max_bytes = UINT64_MAX;
  // Stop when this time is reached (checked every few thousand decisions).
  // Decoding stops this long after its first decision (set-up and the
  // coefficient buffer are not counted); 0 = no limit.
  double max_ms = 0;
  // The floor of a time budget: the deadline does not stop decoding before this
  // many bytes are read (the first bitplanes, which cost little time and carry
  // most of the quality).
  uint64_t min_bytes = 0;
};

struct SpihtDecodeResult {
  uint64_t bytes_used = 0;
  int planes_completed = 0;  // bitplanes whose refinement pass finished
  bool complete = false;     // the traversal reached its end
  bool hit_deadline = false;
};

// Decodes into `coefficients` (dequantised; resized and zeroed here).
SpihtDecodeResult SpihtDecode(const SpihtTree& tree, const SubbandQuantisers& quantisers,
                              const uint8_t* data, size_t size, int planes, EntropyCoder coder,
                              const SpihtDecodeLimits& limits, std::vector<int32_t>* coefficients);

}  // namespace fvv

#endif  // FVV_CODEC_SPIHT4D_H_
