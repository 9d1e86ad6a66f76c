// Coding of one 4D block: the codec's top-level API.
//
// Encode: level shift -> fill unused texels -> 4D wavelet -> subband quantisation ->
// one embedded 4D-SPIHT stream per channel -> rate allocation across channels.
// Decode: per channel, SPIHT (under byte / time budgets) -> inverse wavelet ->
// level shift and clamp. Decoding is integer-only and bit-exact.
#ifndef FVV_CODEC_BLOCK_CODEC_H_
#define FVV_CODEC_BLOCK_CODEC_H_

#include <array>
#include <chrono>
#include <cstdint>
#include <vector>

#include "codec/base/parallel.h"
#include "codec/base/sample_pool.h"
#include "codec/base/status.h"
#include "codec/block.h"
#include "codec/fill.h"
#include "codec/spiht4d.h"
#include "codec/spiht4d_common.h"
#include "codec/subband_weights.h"
#include "codec/wavelet.h"

namespace fvv {

// What a decoder needs besides the streams; carried by the block file and by
// the container's texture payload.
struct BlockParams {
  Shape4D shape;  // luma shape
  WaveletKernel kernel = WaveletKernel::kCdf97;
  EntropyCoder coder = EntropyCoder::kArith;
  ColourSpace colour = ColourSpace::kYCbCr601;
  ChromaFormat chroma = ChromaFormat::k444;
  // Fractional bits f of the transform's samples (SPEC.md 9.6): 0 for Haar and
  // 5/3; for the 9/7, kMinFracBits97..kMaxFracBits97 (2 in streams before
  // format version 3).
  uint8_t frac_bits = kFracBits97;
  // How coefficients are weighted (SPEC.md 9.3): kAxisBands in streams before
  // format version 6 (and block files before version 5); encoders set it.
  BandWeights weights = BandWeights::kAxisBands;
  // Fractional bits p of the decoded samples (SPEC.md 9.6): at most frac_bits
  // and kMaxSampleFrac, 0 with RCT; 0 in streams before format version 7 (and
  // block files before version 6). Encoders take it from the block.
  uint8_t sample_frac = 0;
};

// A point of the encoder's rate-distortion hull of a stream: after `bytes`,
// `distortion` (weighted as the rate allocation weighs the channels) is left.
struct RdPoint {
  uint64_t bytes = 0;
  double distortion = 0;
};

struct ChannelStream {
  uint8_t planes = 0;
  std::vector<uint8_t> data;
  std::vector<TruncationPoint> points;
  // The encoder's convex RD hull, bytes ascending: which bytes buy the most,
  // for laying the channels out in rate order (container/fragment.h). In
  // memory only: no stream carries it, and a stream read back has none.
  std::vector<RdPoint> rd;
};

struct EncodedBlock {
  BlockParams params;
  std::array<ChannelStream, 3> channels;

  uint64_t total_bytes() const {
    return channels[0].data.size() + channels[1].data.size() + channels[2].data.size();
  }
};

enum class RateMode : uint8_t {
  kBitsPerSample,  // value = bpp over luma samples, all three channels together
  kTotalBytes,     // value = bytes for the three streams together
  kPsnr,           // value = target weighted-YUV PSNR in dB over used texels
  kLossless,       // full rate; needs a reversible kernel and the RCT colour space
};

struct EncodeSettings {
  WaveletKernel kernel = WaveletKernel::kCdf97;
  // The 9/7's sample precision f (ignored by the reversible kernels). 2 writes
  // what format versions 1 and 2 read; see subband_weights.h.
  int frac_bits_97 = kFracBits97;
  // kSetSignContexts needs a format version 5 decoder, kNeighbourContexts version 4; kArith is
  // what older ones read.
  EntropyCoder coder = EntropyCoder::kSetSignContexts;
  // kOwnBand needs a format version 6 decoder; kAxisBands is what older ones read.
  BandWeights weights = BandWeights::kOwnBand;
  RateMode rate_mode = RateMode::kBitsPerSample;
  double rate_value = 0.25;
  // Relative weight of each channel's squared error in rate allocation and in the
  // PSNR target. The default makes the YUV error match RGB error (BT.601 inverse).
  std::array<double, 3> channel_weights{1.0, 1.0861, 0.8252};
  // How texels the mask marks unused are filled (codec/fill.h).
  FillOptions fill;
  // Rate-distortion pruning with a bits-per-sample or bytes target: once the
  // cut is known, coefficients that would turn significant only in its lowest
  // bitplane with no significant neighbour are zeroed, the block is coded
  // again, and the result is kept if it decodes with less error at the same
  // bytes, for a second SPIHT encode and two decodes (docs/encoder.md,
  // "Pruning"). Decoders see an ordinary stream. A PSNR target does not
  // prune: its gain is smaller than the PSNR search's tolerance.
  bool prune_isolated = true;
  // The texels a PSNR target counts, where they are fewer than the ones the
  // mask has coded (e.g. what the cameras saw, of what a player may show);
  // null: the mask's. Encoder side only.
  const UsedMask* psnr_mask = nullptr;
  ParallelRunner runner = SerialRunner;
};

struct EncodeReport {
  std::array<uint64_t, 3> channel_bytes{};
  double estimated_psnr = 0;  // from the transform-domain error estimate, all texels
  // When not null: receives what a decoder reconstructs from the whole returned
  // block (the PSNR search's last trial decode when there is one, so callers
  // that measure quality need not decode again).
  Block* decoded = nullptr;
  bool decoded_filled = false;
};

// mask may be null (every texel used); otherwise one byte per luma texel.
StatusOr<EncodedBlock> EncodeBlock(const Block& block, const UsedMask* mask,
                                   const EncodeSettings& settings, EncodeReport* report = nullptr);

struct DecodeBudget {
  uint64_t max_bytes =
      0;              // all channels together; 0 = no limit. Split in proportion to stream sizes.
  double max_ms = 0;  // 0 = no limit; each channel's SPIHT decoding stops this long after it starts
  // Each channel's bytes at most, on top of max_bytes: what a prefix of a
  // fragment whose channels come in chunks holds of each (SPEC.md 3.5.1).
  std::array<uint64_t, 3> channel_max_bytes = {UINT64_MAX, UINT64_MAX, UINT64_MAX};
  // The share of each channel's stream that a time budget never cuts (0 to 1):
  // decoding past max_ms goes on until this much is read.
  double floor_share = 0;
  // Runs the three channels' SPIHT decodes (empty: the main runner). Under a time
  // budget, a runner that runs all three at once keeps them equally far along
  // when the deadline comes; a pool with fewer threads would start the last
  // channel late and leave it starved.
  ParallelRunner channel_runner;
  // Where the channels' sample buffers come from (optional): a pool that
  // recycles the buffers of blocks decoded before.
  SamplePool* sample_pool = nullptr;
};

struct DecodeReport {
  std::array<uint64_t, 3> channel_bytes_read{};
  std::array<int, 3> planes_completed{};
  uint64_t bytes_read = 0;
  bool complete = true;  // every stream decoded to its end (no byte or time budget cut it)
  bool hit_deadline = false;
  double ms = 0;
};

StatusOr<Block> DecodeBlock(const EncodedBlock& encoded, const DecodeBudget& budget,
                            const ParallelRunner& runner, DecodeReport* report = nullptr);

// DecodeBlock in steps, for callers that schedule channels as tasks of their own
// (a GOP's fragments x channels): Start, then SPIHT and reconstruction of each
// channel (channels in any order or in parallel; a channel's Reconstruct after
// its Spiht), then Finish. `encoded` and `budget` must outlive the object.
class BlockDecode {
 public:
  Status Start(const EncodedBlock& encoded, const DecodeBudget& budget);
  // SPIHT decoding of channel c under its share of the byte budget and the time budget.
  void Spiht(int c);
  // Inverse transform and output scaling of channel c, spread over `runner`.
  void Reconstruct(int c, const ParallelRunner& runner);
  // Both, on the calling thread.
  void Channel(int c) {
    Spiht(c);
    Reconstruct(c, SerialRunner);
  }
  Block Finish(DecodeReport* report);

 private:
  const EncodedBlock* encoded_ = nullptr;
  const DecodeBudget* budget_ = nullptr;
  std::chrono::steady_clock::time_point start_;
  std::array<Shape4D, 3> shapes_;
  std::array<SpihtDecodeLimits, 3> limits_;
  std::array<SpihtDecodeResult, 3> results_;
  std::array<std::vector<int32_t>, 3> coeffs_;
};

// The fractional sample bits (codec/block.h) an encoder can give its blocks
// when `requested` are asked for: 0..min(kMaxSampleFrac, frac_bits_97) with the
// 9/7 and own-band weights (format version 7 extends version 6), 0 otherwise.
int UsableSampleFrac(WaveletKernel kernel, int frac_bits_97, BandWeights weights, int requested);

// Validates parameters against the codec's limits (sizes, enum values, planes).
Status ValidateParams(const BlockParams& params);

// Squared-error statistics over used texels (mask may be null), in units of
// the 8-bit scale: samples with sample_frac fractional bits count 2^-sample_frac.
double ChannelMse(const Plane4D& a, const Plane4D& b, const UsedMask* mask, int sample_frac = 0);
double PsnrFromMse(double mse);  // 8-bit peak; 99 dB cap for identical data

}  // namespace fvv

#endif  // FVV_CODEC_BLOCK_CODEC_H_
