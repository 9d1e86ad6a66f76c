#include <algorithm>
#include <cstdlib>

#include "codec/bit_io.h"
#include "codec/large_buffer.h"
#include "codec/logistic_mixing.h"
#include "codec/quadtree4d.h"
#include "codec/range_coder.h"
#include "codec/spiht4d.h"

namespace fvv {
namespace {

uint8_t BitLength(uint32_t v) {
  uint8_t n = 0;
  while (v) {
    ++n;
    v >>= 1;
  }
  return n;
}

class EncoderSide {
 public:
  EncoderSide(const SpihtTree& tree, const SubbandQuantisers& quantisers,
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

  // What the traversal asks: SPIHT's sets, or coder 4's quadtree nodes.
  void PrepareSets() {
    AssignLarge(&descendant_bits_, mag_.size());
    AssignLarge(&grandchild_bits_, mag_.size());
    ComputeSetMagnitudes();
  }
  // Per node of `layout`, the bit length of the largest magnitude under it.
  void PrepareNodes(const QuadtreeLayout& layout) {
    node_bits_.assign(layout.nodes(), 0);
    for (const QuadtreeBand& b : layout.bands()) {
      // Level 0 from the coefficients, then each level from the one below.
      for (int k = 0; k <= b.top; ++k) {
        const auto& d = b.dims[k];
        std::array<uint32_t, kAxes> p, half;
        for (p[0] = 0; p[0] < d[0]; ++p[0])
          for (p[1] = 0; p[1] < d[1]; ++p[1])
            for (p[2] = 0; p[2] < d[2]; ++p[2])
              for (p[3] = 0; p[3] < d[3]; ++p[3]) {
                const uint32_t node = b.Node(k, p);
                if (k == 0) node_bits_[node] = BitLength(mag_[layout.Coefficient(b, p)]);
                if (k == b.top) continue;
                for (int a = 0; a < kAxes; ++a) half[a] = p[a] >> 1;
                uint8_t& parent = node_bits_[b.Node(k + 1, half)];
                parent = std::max(parent, node_bits_[node]);
              }
      }
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
  bool SigSet(uint32_t idx, int n, bool type_b, int ctx, bool* sig) {
    *sig = (type_b ? grandchild_bits_[idx] : descendant_bits_[idx]) > n;
    return Put(ctx, *sig);
  }
  bool SigNode(uint32_t node, int n, int ctx, bool* sig) {
    *sig = node_bits_[node] > n;
    return Put(ctx, *sig);
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

 private:
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

  // Bit lengths of the OR of |v| over D(x) and over L(x), bottom-up by level.
  void ComputeSetMagnitudes() {
    const WaveletGeometry& g = tree_.geometry();
    if (g.levels == 0) return;
    std::vector<std::vector<uint32_t>> by_level(g.levels + 2);
    std::array<uint32_t, kAxes> ext;
    for (int a = 0; a < kAxes; ++a) ext[a] = g.RegionExtent(a, 1);
    std::array<uint32_t, kAxes> p;
    for (p[0] = 0; p[0] < ext[0]; ++p[0])
      for (p[1] = 0; p[1] < ext[1]; ++p[1])
        for (p[2] = 0; p[2] < ext[2]; ++p[2])
          for (p[3] = 0; p[3] < ext[3]; ++p[3])
            by_level[tree_.Level(p)].push_back(
                static_cast<uint32_t>(g.shape.Index(p[0], p[1], p[2], p[3])));
    uint32_t children[kMaxChildren];
    for (int l = 2; l <= g.levels + 1; ++l) {
      for (uint32_t idx : by_level[l]) {
        const int nc = tree_.Children(idx, children);
        uint8_t d = 0, gc = 0;
        for (int k = 0; k < nc; ++k) {
          const uint32_t c = children[k];
          d = std::max({d, BitLength(mag_[c]), descendant_bits_[c]});
          gc = std::max(gc, descendant_bits_[c]);
        }
        descendant_bits_[idx] = d;
        grandchild_bits_[idx] = gc;
      }
    }
  }

  const SpihtTree& tree_;
  const SubbandQuantisers& quantisers_;
  EntropyCoder coder_;
  uint64_t max_bytes_;
  std::vector<uint32_t> mag_;
  std::vector<uint8_t> negative_;
  std::vector<uint8_t> descendant_bits_;
  std::vector<uint8_t> grandchild_bits_;
  std::vector<uint8_t> node_bits_;  // coder 4
  std::vector<uint16_t> probs_;     // coders 1 and 2: adapt by 1/32
  // Coders 3 and 4: adapt by 1/2, 1/4, .. 1/32 over a context's first decisions.
  std::vector<mixing::CountedProb> counted_probs_;
  BitWriter bits_;
  RangeEncoder range_;
  double distortion_ = 0;
  SpihtEncoded out_;
};

}  // namespace

SpihtEncoded SpihtEncode(const SpihtTree& tree, const SubbandQuantisers& quantisers,
                         const std::vector<int32_t>& coefficients, EntropyCoder coder,
                         uint64_t max_bytes) {
  EncoderSide side(tree, quantisers, coefficients, coder, max_bytes);
  const int planes = std::min(side.planes(), kMaxBitplanes);
  side.MarkStart();
  if (coder == EntropyCoder::kArith4) {
    const QuadtreeLayout layout(tree.geometry());
    side.PrepareNodes(layout);
    QuadtreeTraversal<EncoderSide>(layout, &side).Run(planes);
  } else {
    side.PrepareSets();
    SpihtTraverse(coder, tree, planes, &side);
  }
  return side.Finish(planes);
}

}  // namespace fvv
