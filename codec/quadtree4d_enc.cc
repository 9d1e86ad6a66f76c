#include <algorithm>
#include <array>

#include "codec/bitplane_enc.h"
#include "codec/quadtree4d.h"
#include "codec/quadtree4d_common.h"

namespace fvv {
namespace {

// The quadtree's side: the bit length of the largest magnitude under each node.
class QuadtreeEncoderSide : public BitplaneEncoder {
 public:
  using BitplaneEncoder::BitplaneEncoder;

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

  bool SigNode(uint32_t node, int n, int ctx, bool* sig) {
    *sig = node_bits_[node] > n;
    return Put(ctx, *sig);
  }

 private:
  std::vector<uint8_t> node_bits_;
};

}  // namespace

SpihtEncoded QuadtreeEncode(const SpihtTree& tree, const SubbandQuantisers& quantisers,
                            const std::vector<int32_t>& coefficients, uint64_t max_bytes) {
  QuadtreeEncoderSide side(tree, quantisers, coefficients, EntropyCoder::kQuadtree, max_bytes);
  const int planes = std::min(side.planes(), kMaxBitplanes);
  side.MarkStart();
  const QuadtreeLayout layout(tree.geometry());
  side.PrepareNodes(layout);
  QuadtreeTraversal<QuadtreeEncoderSide>(layout, &side).Run(planes);
  return side.Finish(planes);
}

}  // namespace fvv
