// The decoder's side of the embedded bitplane coders (SPIHT, coders 0 to 3, and
// the quadtree, coder 4): the decisions' entropy decoding under byte and time
// budgets, and the reconstruction of the significant coefficients. A set test
// and a node test are the same decision for the decoder.
#ifndef FVV_CODEC_BITPLANE_DEC_H_
#define FVV_CODEC_BITPLANE_DEC_H_

#include <chrono>
#include <vector>

#include "codec/base/bit_io.h"
#include "codec/logistic_mixing.h"
#include "codec/range_coder.h"
#include "codec/spiht4d.h"

namespace fvv {

inline constexpr uint32_t kDeadlineCheckInterval = 4096;
inline constexpr uint8_t kNegativeFlag = 0x80;

class BitplaneDecoder {
 public:
  BitplaneDecoder(const SpihtTree& tree, const uint8_t* data, size_t budget, EntropyCoder coder,
                  const SpihtDecodeLimits& limits, std::vector<int32_t>* magnitudes)
      : coder_(coder),
        min_bytes_(limits.min_bytes),
        bits_(data, budget),
        range_(data, budget),
        deadline_(std::chrono::steady_clock::time_point::max()),
        mag_(*magnitudes),
        state_(StateBuffer(tree.size())),
        probs_(kMaxContexts, kProbInit),
        counted_probs_(CountAdaptive(coder) ? kMaxContexts : 0) {
    // The clock starts after the buffers above exist: the budget is for decisions.
    if (limits.max_ms > 0) {
      deadline_ = std::chrono::steady_clock::now() +
                  std::chrono::microseconds(static_cast<int64_t>(limits.max_ms * 1000));
    }
  }

  bool SigCoeff(uint32_t, int, int ctx, bool* sig) {
    uint32_t bit;
    if (!Get(ctx, &bit)) return false;
    *sig = bit != 0;
    return true;
  }
  bool Sign(uint32_t idx, int n, int ctx, bool* is_negative) {
    uint32_t negative;
    if (!Get(ctx, &negative)) return false;
    *is_negative = negative != 0;
    mag_[idx] = static_cast<int32_t>(1u << n);
    state_[idx] = static_cast<uint8_t>(n | (negative ? kNegativeFlag : 0));
    significant_.push_back(idx);
    return true;
  }
  bool SigNode(uint32_t, int, int ctx, bool* sig) { return SigSet(0, 0, false, ctx, sig); }
  bool SigSet(uint32_t, int, bool, int ctx, bool* sig) {
    uint32_t bit;
    if (!Get(ctx, &bit)) return false;
    *sig = bit != 0;
    return true;
  }
  bool Refine(uint32_t idx, int n, int ctx) {
    uint32_t bit;
    if (!Get(ctx, &bit)) return false;
    if (bit) mag_[idx] |= static_cast<int32_t>(1u << n);
    state_[idx] = static_cast<uint8_t>((state_[idx] & kNegativeFlag) | n);
    return true;
  }
  void PassEnd(int, int pass) {
    if (pass == 1) ++planes_completed_;
  }

  // Midpoint reconstruction of every significant coefficient, then dequantisation.
  void Reconstruct(const SpihtTree& tree, const SubbandQuantisers& quantisers) {
    for (uint32_t idx : significant_) {
      const int plane = state_[idx] & 0x1F;
      uint32_t m = static_cast<uint32_t>(mag_[idx]);
      m += (3u << plane) >> 3;  // 3/8 of the unknown interval: magnitudes are skewed low
      const int32_t c = DequantiseMagnitude(m, quantisers[tree.BandId(idx)].inv_q16);
      mag_[idx] = (state_[idx] & kNegativeFlag) ? -c : c;
    }
  }

  SpihtDecodeResult Result() const {
    SpihtDecodeResult result;
    result.bytes_used = bytes_used();
    result.planes_completed = planes_completed_;
    result.complete = !stopped_;
    result.hit_deadline = hit_deadline_;
    return result;
  }

  uint64_t bytes_used() const {
    return RangeCoded(coder_) ? range_.bytes_consumed() : bits_.bytes_consumed();
  }
  int planes_completed() const { return planes_completed_; }
  bool hit_deadline() const { return hit_deadline_; }
  bool stopped() const { return stopped_; }

 private:
  bool Get(int ctx, uint32_t* bit) {
    // Past the deadline, decoding goes on until the floor's bytes are read.
    if (++decisions_ % kDeadlineCheckInterval == 0 &&
        std::chrono::steady_clock::now() >= deadline_ && bytes_used() >= min_bytes_) {
      hit_deadline_ = true;
    }
    if (hit_deadline_) return Stop();
    if (RangeCoded(coder_)) {
      if (!range_.ok()) return Stop();
      if (!counted_probs_.empty()) {
        mixing::CountedProb& m = counted_probs_[ctx];
        *bit = range_.DecodeWithProbability(m.p0);
        mixing::Update(*bit, &m);
      } else {
        *bit = range_.Decode(&probs_[ctx]);
      }
    } else {
      if (!bits_.CanRead(1)) return Stop();
      *bit = bits_.GetBit();
    }
    return true;
  }
  bool Stop() {
    stopped_ = true;
    return false;
  }

  // Per-coefficient state, read only where Sign has written it first, so a
  // per-thread buffer is reused without clearing.
  static uint8_t* StateBuffer(size_t n) {
    thread_local std::vector<uint8_t> buffer;
    if (buffer.size() < n) buffer.resize(n);
    return buffer.data();
  }

  EntropyCoder coder_;
  uint64_t min_bytes_;
  BitReader bits_;
  RangeDecoder range_;
  std::chrono::steady_clock::time_point deadline_;
  std::vector<int32_t>& mag_;
  uint8_t* state_;  // bit 7: negative; bits 0-4: lowest bitplane known
  std::vector<uint32_t> significant_;
  std::vector<uint16_t> probs_;  // coders 1 and 2: adapt by 1/32
  // Coders 3 and 4: adapt by 1/2, 1/4, .. 1/32 over a context's first decisions.
  std::vector<mixing::CountedProb> counted_probs_;
  uint64_t decisions_ = 0;
  int planes_completed_ = 0;
  bool hit_deadline_ = false;
  bool stopped_ = false;
};

}  // namespace fvv

#endif  // FVV_CODEC_BITPLANE_DEC_H_
