#include <algorithm>
#include <array>

#include "codec/bitplane_enc.h"
#include "codec/quadtree4d.h"
#include "codec/spiht4d.h"

namespace fvv {
namespace {

// SPIHT's side: the bit lengths of the largest magnitude under each set.
class SpihtEncoderSide : public BitplaneEncoder {
 public:
  using BitplaneEncoder::BitplaneEncoder;

  void PrepareSets() {
    AssignLarge(&descendant_bits_, mag_.size());
    AssignLarge(&grandchild_bits_, mag_.size());
    ComputeSetMagnitudes();
  }
  bool SigSet(uint32_t idx, int n, bool type_b, int ctx, bool* sig) {
    *sig = (type_b ? grandchild_bits_[idx] : descendant_bits_[idx]) > n;
    return Put(ctx, *sig);
  }

 private:
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

  std::vector<uint8_t> descendant_bits_;
  std::vector<uint8_t> grandchild_bits_;
};

}  // namespace

SpihtEncoded SpihtEncode(const SpihtTree& tree, const SubbandQuantisers& quantisers,
                         const std::vector<int32_t>& coefficients, EntropyCoder coder,
                         uint64_t max_bytes) {
  if (coder == EntropyCoder::kQuadtree) {
    return QuadtreeEncode(tree, quantisers, coefficients, max_bytes);
  }
  SpihtEncoderSide side(tree, quantisers, coefficients, coder, max_bytes);
  const int planes = std::min(side.planes(), kMaxBitplanes);
  side.MarkStart();
  side.PrepareSets();
  SpihtTraverse(coder, tree, planes, &side);
  return side.Finish(planes);
}

}  // namespace fvv
