// DecodeBlock: SPIHT per channel under byte and time budgets, inverse
// transform, output scaling. Integer-only and bit-exact (SPEC.md 9).
#include <algorithm>
#include <chrono>
#include <cmath>

#include "codec/base/simd.h"
#include "codec/block_codec.h"
#include "codec/spiht4d.h"
#include "codec/subband_weights.h"

namespace fvv {
namespace {

// Output scaling (SPEC.md 9.6) of samples [begin, end), in 32-bit arithmetic
// so it vectorises: clamping to +-2^30 first changes no result (such values
// clamp to the range anyway) and keeps the sums from overflowing.
FVV_SIMD_CLONES
void ScaleOutput(int32_t* data, size_t begin, size_t end, int32_t round, int frac, int32_t offset,
                 int32_t lo, int32_t hi) {
  for (size_t i = begin; i < end; ++i) {
    const int32_t s = std::min(std::max(data[i], -(1 << 30)), 1 << 30);
    const int32_t v = ((s + round) >> frac) + offset;
    data[i] = std::min(std::max(v, lo), hi);
  }
}

}  // namespace

Status BlockDecode::Start(const EncodedBlock& encoded, const DecodeBudget& budget) {
  start_ = std::chrono::steady_clock::now();
  encoded_ = &encoded;
  budget_ = &budget;
  const BlockParams& p = encoded.params;
  FVV_RETURN_IF_ERROR(ValidateParams(p));
  for (int c = 0; c < 3; ++c)
    if (encoded.channels[c].planes > kMaxBitplanes)
      return Corrupt("channel " + std::to_string(c) + " declares " +
                     std::to_string(encoded.channels[c].planes) + " bitplanes (at most " +
                     std::to_string(kMaxBitplanes) + ")");
  shapes_ = {p.shape, ChromaShape(p.shape, p.chroma), ChromaShape(p.shape, p.chroma)};
  const uint64_t total = encoded.total_bytes();
  for (int c = 0; c < 3; ++c) {
    limits_[c] = SpihtDecodeLimits{};
    if (budget.max_bytes > 0 && budget.max_bytes < total) {
      // Same fraction of every stream: the streams were allocated at equal RD slope,
      // so equal fractions keep them close to it. Integer arithmetic, because the
      // conformance suite pins the result (SPEC.md Annex B).
      using Wide = unsigned __int128;
      limits_[c].max_bytes =
          static_cast<uint64_t>(Wide{encoded.channels[c].data.size()} * budget.max_bytes / total);
    }
    limits_[c].max_bytes = std::min(limits_[c].max_bytes, budget.channel_max_bytes[c]);
    if (budget.floor_share > 0) {
      const double share = std::min(1.0, budget.floor_share);
      limits_[c].min_bytes =
          static_cast<uint64_t>(std::ceil(share * double(encoded.channels[c].data.size())));
    }
    if (budget.sample_pool) coeffs_[c] = budget.sample_pool->Take();
  }
  return Status::Ok();
}

void BlockDecode::Spiht(int c) {
  const WaveletGeometry g(shapes_[c]);
  const std::shared_ptr<const SpihtTree> tree = SharedSpihtTree(g);
  const SubbandQuantisers q(encoded_->params.kernel, encoded_->params.frac_bits,
                            encoded_->params.weights, g);
  const ChannelStream& s = encoded_->channels[c];
  // The time budget is for decoding decisions: it starts once the channel's
  // set-up is done (which no budget could shorten).
  limits_[c].max_ms = budget_->max_ms;
  results_[c] = SpihtDecode(*tree, q, s.data.data(), s.data.size(), s.planes,
                            encoded_->params.coder, limits_[c], &coeffs_[c]);
}

void BlockDecode::Reconstruct(int c, const ParallelRunner& runner) {
  const BlockParams& p = encoded_->params;
  // Output with sample_frac fractional bits: the transform's frac_bits less those.
  const int frac = p.frac_bits - p.sample_frac;
  const WaveletGeometry g(shapes_[c]);
  const SampleRange range = ChannelRange(p.colour, c, p.sample_frac);
  const int32_t round = frac ? 1 << (frac - 1) : 0;
  int32_t* data = coeffs_[c].data();
  // Output scaling of each part as soon as the transform is done with it
  // (while it is still in cache where the transform works plane by plane).
  InverseTransform4D(p.kernel, g, runner, data, [&](size_t begin, size_t end) {
    ScaleOutput(data, begin, end, round, frac, range.offset, range.min, range.max);
  });
}

Block BlockDecode::Finish(DecodeReport* report) {
  Block block;
  block.colour = encoded_->params.colour;
  block.chroma = encoded_->params.chroma;
  block.sample_frac = encoded_->params.sample_frac;
  for (int c = 0; c < 3; ++c) {
    block.channels[c].shape = shapes_[c];
    block.channels[c].samples = std::move(coeffs_[c]);
  }
  if (report) {
    report->bytes_read = 0;
    report->complete = true;
    report->hit_deadline = false;
    for (int c = 0; c < 3; ++c) {
      report->channel_bytes_read[c] = results_[c].bytes_used;
      report->planes_completed[c] = results_[c].planes_completed;
      report->bytes_read += results_[c].bytes_used;
      // Complete: the stream ended (by its own end or the encoder's cut), not a budget.
      report->complete = report->complete && !results_[c].hit_deadline &&
                         limits_[c].max_bytes >= encoded_->channels[c].data.size();
      report->hit_deadline = report->hit_deadline || results_[c].hit_deadline;
    }
    report->ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_)
            .count();
  }
  return block;
}

StatusOr<Block> DecodeBlock(const EncodedBlock& encoded, const DecodeBudget& budget,
                            const ParallelRunner& runner, DecodeReport* report) {
  BlockDecode decode;
  FVV_RETURN_IF_ERROR(decode.Start(encoded, budget));
  if (budget.channel_runner) {
    // A time budget's runner keeps the channels' SPIHT decodes equally far
    // along: nothing else runs beside them until all three have stopped.
    budget.channel_runner(3, [&](uint32_t c) { decode.Spiht(static_cast<int>(c)); });
    for (int c = 0; c < 3; ++c) decode.Reconstruct(c, runner);
  } else {
    // Each channel's inverse transform starts as soon as its own SPIHT decode
    // ends: luma's decode is the longest, and the chroma channels' transforms
    // fill the time it leaves the other threads. A pool's idle threads join
    // each transform (ThreadPool runs nested sections in parallel).
    runner(3, [&](uint32_t c) {
      decode.Spiht(static_cast<int>(c));
      decode.Reconstruct(static_cast<int>(c), runner);
    });
  }
  return decode.Finish(report);
}

}  // namespace fvv
