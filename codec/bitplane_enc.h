// The encoder's side of the embedded bitplane coders (SPIHT, coders 0 to 3, and
// the quadtree, coder 4): the decisions' entropy coding, the truncation points
// and the rate-distortion curve that rate allocation reads. Each coder derives
// its own side, adding the set or node tests its traversal asks for.
#ifndef FVV_CODEC_BITPLANE_ENC_H_
#define FVV_CODEC_BITPLANE_ENC_H_

#include <algorithm>
#include <cstdlib>
#include <vector>

#include "codec/base/bit_io.h"
#include "codec/base/large_buffer.h"
#include "codec/logistic_mixing.h"
#include "codec/range_coder.h"
#include "codec/spiht4d.h"

namespace fvv {

inline uint8_t BitLength(uint32_t v) {
  uint8_t n = 0;
  while (v) {
    ++n;
    v >>= 1;
  }
  return n;
}

class BitplaneEncoder {
 public:
  BitplaneEncoder(const SpihtTree& tree, const SubbandQuantisers& quantisers,
                  const std::vector<int32_t>& coefficients, EntropyCoder coder, uint64_t max_bytes)
      : tree_(tree),
        quantisers_(quantisers),
        coder_(coder),
        max_bytes_(max_bytes),
        probs_(kMaxContexts, kProbInit),
        counted_probs_(CountAdaptive(coder) ? kMaxContexts : 0) {
    AssignLarge(&mag_, coefficients.size());
    AssignLarge(&negative_, coefficients.size());
    for (size_t i = 0; i < coefficients.size(); ++i) {
      mag_[i] = static_cast<uint32_t>(std::abs(coefficients[i]));
      negative_[i] = coefficients[i] < 0;
      const double v = mag_[i];
      if (v != 0) distortion_ += Factor(static_cast<uint32_t>(i)) * v * v;
    }
  }

  int planes() const {
    uint32_t all = 0;
    for (uint32_t m : mag_) all |= m;
    return BitLength(all);
  }

  bool SigCoeff(uint32_t idx, int n, int ctx, bool* sig) {
    *sig = (mag_[idx] >> n) != 0;
    return Put(ctx, *sig);
  }
  bool Sign(uint32_t idx, int n, int ctx, bool* negative) {
    // Newly significant: reconstruction moves from 0 to 3/8 into [2^n, 2^(n+1)).
    const double v = mag_[idx];
    const double rec = static_cast<double>((1u << n) + ((3u << n) >> 3));
    distortion_ += Factor(idx) * ((v - rec) * (v - rec) - v * v);
    *negative = negative_[idx];
    return Put(ctx, *negative);
  }
  bool Refine(uint32_t idx, int n, int ctx) {
    const uint32_t m = mag_[idx];
    const double v = m;
    const double known_above = static_cast<double>((m >> (n + 1)) << (n + 1));
    const double old_rec = known_above + ((3u << (n + 1)) >> 3);
    const double known = static_cast<double>((m >> n) << n);
    const double new_rec = known + ((3u << n) >> 3);
    distortion_ += Factor(idx) * ((v - new_rec) * (v - new_rec) - (v - old_rec) * (v - old_rec));
    return Put(ctx, (m >> n) & 1);
  }
  void PassEnd(int n, int pass) {
    const uint64_t bytes = BytesNeeded();
    out_.points.push_back(
        {static_cast<uint32_t>(bytes), static_cast<uint8_t>(n), static_cast<uint8_t>(pass)});
    out_.rd_bytes.push_back(bytes);
    out_.rd_distortion.push_back(distortion_);
  }

  SpihtEncoded Finish(int planes) {
    out_.planes = static_cast<uint8_t>(planes);
    out_.data = RangeCoded(coder_) ? range_.Finish() : bits_.Finish();
    if (out_.data.size() > max_bytes_) {
      // Cut at the budget; a pass that ended beyond it is no longer a truncation point.
      out_.data.resize(max_bytes_);
      while (!out_.points.empty() && out_.points.back().bytes > max_bytes_) out_.points.pop_back();
      while (!out_.rd_bytes.empty() && out_.rd_bytes.back() > max_bytes_) {
        out_.rd_bytes.pop_back();
        out_.rd_distortion.pop_back();
      }
      // The partial pass up to the cut.
      out_.rd_bytes.push_back(max_bytes_);
      out_.rd_distortion.push_back(distortion_);
    }
    return std::move(out_);
  }

  void MarkStart() {
    out_.rd_bytes.push_back(0);
    out_.rd_distortion.push_back(distortion_);
  }

 protected:
  double Factor(uint32_t idx) const { return quantisers_[tree_.BandId(idx)].distortion; }
  uint64_t BytesNeeded() const {
    return RangeCoded(coder_) ? range_.BytesNeeded() : (bits_.bit_count() + 7) / 8;
  }
  bool Put(int ctx, uint32_t bit) {
    if (!counted_probs_.empty()) {
      mixing::CountedProb& m = counted_probs_[ctx];
      range_.EncodeWithProbability(bit, m.p0);
      mixing::Update(bit, &m);
    } else if (RangeCoded(coder_)) {
      range_.Encode(bit, &probs_[ctx]);
    } else {
      bits_.PutBit(bit);
    }
    return BytesNeeded() <= max_bytes_;
  }

  const SpihtTree& tree_;
  const SubbandQuantisers& quantisers_;
  EntropyCoder coder_;
  uint64_t max_bytes_;
  std::vector<uint32_t> mag_;
  std::vector<uint8_t> negative_;
  std::vector<uint16_t> probs_;  // coders 1 and 2: adapt by 1/32
  // Coders 3 and 4: adapt by 1/2, 1/4, .. 1/32 over a context's first decisions.
  std::vector<mixing::CountedProb> counted_probs_;
  BitWriter bits_;
  RangeEncoder range_;
  double distortion_ = 0;
  SpihtEncoded out_;
};

}  // namespace fvv

#endif  // FVV_CODEC_BITPLANE_ENC_H_
