// Coder 4's layout and traversal, shared by its encoder and decoder: the
// significance of each subband coded with a quadtree over the band (in 4D a
// tree that halves every axis longer than one node), decisions modelled on the
// neighbours at the node's tree level, the parent band's node and time. The
// bands, their order and parents, the tree grids, the lists (LIN per tree
// level, LSP), the traversal and every context index are specified in SPEC.md
// 9.9, whose terms the names below follow; why a second significance coder,
// and what it gains where, is in docs/encoder.md ("Coder 4"). Truncation
// points and reconstruction are SPIHT's (spiht4d.h).
#ifndef FVV_CODEC_QUADTREE4D_COMMON_H_
#define FVV_CODEC_QUADTREE4D_COMMON_H_

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "codec/wavelet.h"

namespace fvv {

struct QuadtreeBand {
  std::array<uint32_t, kAxes> lo{};  // the band's first coefficient along each axis
  std::array<uint32_t, kAxes> n{};   // its extent
  int level = 0;                     // 1..L, or L + 1 for the final low band
  uint8_t axes = 0;                  // bit a: axis a is high-pass (m above)
  // Context class: 0 level 1, 1 level 2, 2 level >= 3, 3 the final low band.
  uint8_t cls = 0;
  int parent = -1;  // index of the parent band, or -1
  // Per axis: the parent band is shorter (halved by the split), so a node of
  // level k covers what the parent's node at level k - 1 covers.
  std::array<bool, kAxes> parent_halved{};
  int top = 0;
  std::vector<std::array<uint32_t, kAxes>> dims;  // grid extents at levels 0..top
  std::vector<uint32_t> offset;                   // first node of each level in the node array

  // The node array index of node p (raster order, x fastest) at level k, and back.
  uint32_t Node(int k, const std::array<uint32_t, kAxes>& p) const {
    const auto& d = dims[k];
    return offset[k] + ((p[0] * d[1] + p[1]) * d[2] + p[2]) * d[3] + p[3];
  }
  void NodeCoords(int k, uint32_t node, std::array<uint32_t, kAxes>* p) const {
    const auto& d = dims[k];
    uint32_t q = node - offset[k];
    for (int a = kAxes - 1; a > 0; --a) {
      (*p)[a] = q % d[a];
      q /= d[a];
    }
    (*p)[0] = q;
  }
};

class QuadtreeLayout {
 public:
  explicit QuadtreeLayout(const WaveletGeometry& geometry);

  const Shape4D& shape() const { return shape_; }
  const std::vector<QuadtreeBand>& bands() const { return bands_; }
  size_t nodes() const { return nodes_; }
  int top() const { return top_; }  // the largest top of any band

  // The block index of coefficient p (band coordinates) of band b.
  uint32_t Coefficient(const QuadtreeBand& b, const std::array<uint32_t, kAxes>& p) const {
    return static_cast<uint32_t>(
        shape_.Index(b.lo[0] + p[0], b.lo[1] + p[1], b.lo[2] + p[2], b.lo[3] + p[3]));
  }

 private:
  Shape4D shape_;
  std::vector<QuadtreeBand> bands_;
  size_t nodes_ = 0;
  int top_ = 0;
};

// Context indices of coder 4. A node's significance is modelled on: whether it
// is a coefficient (k = 0) or a node above; its band's class; its significant
// neighbours at its level in its band (k = 0: horizontal 0-2, vertical 0-2,
// diagonal 0-2+, with horizontal and vertical exchanged in bands high-pass in
// x alone, as JPEG 2000 orients its contexts; k > 0: horizontal and vertical
// together 0-2+, diagonal 0-2+); the parent band's matching node
// (insignificant, significant, no parent band); a significant neighbour at
// t - 1 or t + 1. A child coded under a node just found significant has its
// own contexts, split further by its significant siblings before it (0, 1, 2+).
namespace ctx4 {
constexpr int kNeighbourBins = 27;
constexpr int kParentBins = 3;
constexpr int kClasses = 4;
constexpr int kSigLin = 0;  // [k > 0][class][neighbours][parent][temporal]
constexpr int kSigLinCount = 2 * kClasses * kNeighbourBins * kParentBins * 2;
constexpr int kSigChild = kSigLin + kSigLinCount;  // [..][siblings][temporal]
constexpr int kSigChildCount = kSigLinCount * 3;
// Sign: [class][horizontal sum][vertical sum][temporal sum], each 0, > 0, < 0.
constexpr int kSign = kSigChild + kSigChildCount;
constexpr int kRefine = kSign + kClasses * 27;  // [class][first][spatial neighbours 0-2]
constexpr int kCount = kRefine + kClasses * 6;
}  // namespace ctx4

// The traversal. Side provides (each returns false to stop now):
//   bool SigNode(uint32_t node, int n, int ctx, bool* sig);
//   bool Sign(uint32_t coefficient, int n, int ctx, bool* negative);
//   bool Refine(uint32_t coefficient, int n, int ctx);
//   void PassEnd(int n, int pass);
template <class Side>
class QuadtreeTraversal {
 public:
  QuadtreeTraversal(const QuadtreeLayout& layout, Side* side)
      : layout_(layout), bands_(layout.bands()), side_(side) {}

  void Run(int planes) {
    thread_local std::vector<uint8_t> state;
    state.assign(layout_.nodes(), 0);
    state_ = state.data();
    lin_.assign(static_cast<size_t>(layout_.top()) + 1, {});
    for (uint32_t b = 0; b < bands_.size(); ++b)
      lin_[bands_[b].top].push_back({bands_[b].offset[bands_[b].top], b});
    size_t lsp_first_refine = 0;  // LSP entries before this one have been refined before
    for (int n = planes - 1; n >= 0; --n) {
      const size_t lsp_before = lsp_.size();
      for (int k = 0; k <= layout_.top(); ++k) {
        // Entries appended below come from higher levels and go to lower lists.
        std::vector<Entry>& list = lin_[k];
        size_t kept = 0;
        for (size_t i = 0; i < list.size(); ++i) {
          const Entry e = list[i];
          const QuadtreeBand& b = bands_[e.band];
          Coords p;
          b.NodeCoords(k, e.node, &p);
          bool sig;
          if (!side_->SigNode(e.node, n, SigContext(ctx4::kSigLin, b, k, p, e.node), &sig)) return;
          if (!sig) {
            list[kept++] = e;
          } else if (!Significant(e.band, k, p, e.node, n)) {
            return;
          }
        }
        list.resize(kept);
      }
      side_->PassEnd(n, 0);
      for (size_t i = 0; i < lsp_before; ++i) {
        const Leaf& leaf = lsp_[i];
        if (!side_->Refine(leaf.coefficient, n, RefineContext(leaf, i >= lsp_first_refine))) return;
      }
      lsp_first_refine = lsp_before;
      side_->PassEnd(n, 1);
    }
  }

 private:
  using Coords = std::array<uint32_t, kAxes>;
  struct Entry {
    uint32_t node;
    uint32_t band;
  };
  struct Leaf {
    uint32_t coefficient;
    uint32_t node;
    uint32_t band;
    uint8_t neighbours;  // which of x - 1, x + 1, y - 1, y + 1 lie in the band
  };

  // Neighbour counts at level k of band b around p.
  int SigContext(int base, const QuadtreeBand& b, int k, const Coords& p, uint32_t node,
                 int siblings = -1) const {
    const auto& d = b.dims[k];
    const uint32_t sx = 1, sy = d[3], st = d[1] * d[2] * d[3];
    const bool left = p[3] > 0, right = p[3] + 1 < d[3];
    const bool up = p[2] > 0, down = p[2] + 1 < d[2];
    int h = 0, v = 0, diag = 0, t = 0;
    if (left) h += state_[node - sx] != 0;
    if (right) h += state_[node + sx] != 0;
    if (up) {
      v += state_[node - sy] != 0;
      if (left) diag += state_[node - sy - sx] != 0;
      if (right) diag += state_[node - sy + sx] != 0;
    }
    if (down) {
      v += state_[node + sy] != 0;
      if (left) diag += state_[node + sy - sx] != 0;
      if (right) diag += state_[node + sy + sx] != 0;
    }
    if (p[0] > 0) t += state_[node - st] != 0;
    if (p[0] + 1 < d[0]) t += state_[node + st] != 0;
    if (b.axes == 8) std::swap(h, v);  // high-pass in x alone: vertical neighbours lead
    diag = std::min(diag, 2);
    const int nb = k == 0 ? (h * 3 + v) * 3 + diag : std::min(h + v, 2) * 3 + diag;
    int parent = 2;
    if (b.parent >= 0) {
      const QuadtreeBand& pb = bands_[b.parent];
      // The parent's level k - 1 (a shorter band may have fewer levels).
      const int pk = std::min(k > 0 ? k - 1 : 0, pb.top);
      Coords q;
      for (int a = 0; a < kAxes; ++a) {
        const uint32_t c =
            b.parent_halved[a] ? (k > 0 ? p[a] : p[a] >> 1) : (k > 0 ? 2 * p[a] : p[a]);
        q[a] = std::min(c, pb.dims[pk][a] - 1);
      }
      parent = state_[pb.Node(pk, q)] != 0;
    }
    int c = (((k > 0) * ctx4::kClasses + b.cls) * ctx4::kNeighbourBins + nb) * ctx4::kParentBins +
            parent;
    if (siblings >= 0) c = c * 3 + std::min(siblings, 2);
    return base + c * 2 + (t > 0);
  }

  int SignContext(const QuadtreeBand& b, const Coords& p, uint32_t node) const {
    const auto& d = b.dims[0];
    const uint32_t sy = d[3], st = d[1] * d[2] * d[3];
    auto sign = [&](uint32_t i) { return state_[i] == 0 ? 0 : state_[i] == 1 ? 1 : -1; };
    int h = 0, v = 0, t = 0;
    if (p[3] > 0) h += sign(node - 1);
    if (p[3] + 1 < d[3]) h += sign(node + 1);
    if (p[2] > 0) v += sign(node - sy);
    if (p[2] + 1 < d[2]) v += sign(node + sy);
    if (p[0] > 0) t += sign(node - st);
    if (p[0] + 1 < d[0]) t += sign(node + st);
    auto bin = [](int s) { return s > 0 ? 1 : s < 0 ? 2 : 0; };
    return ctx4::kSign + ((b.cls * 3 + bin(h)) * 3 + bin(v)) * 3 + bin(t);
  }

  int RefineContext(const Leaf& leaf, bool first) const {
    const QuadtreeBand& b = bands_[leaf.band];
    const uint32_t sy = b.dims[0][3];
    int k = 0;
    if (leaf.neighbours & 1) k += state_[leaf.node - 1] != 0;
    if (leaf.neighbours & 2) k += state_[leaf.node + 1] != 0;
    if (leaf.neighbours & 4) k += state_[leaf.node - sy] != 0;
    if (leaf.neighbours & 8) k += state_[leaf.node + sy] != 0;
    return ctx4::kRefine + (b.cls * 2 + first) * 3 + std::min(k, 2);
  }

  // Node (band bi, level k, p) was found significant in plane n.
  bool Significant(uint32_t bi, int k, const Coords& p, uint32_t node, int n) {
    const QuadtreeBand& b = bands_[bi];
    if (k == 0) {
      const uint32_t coefficient = layout_.Coefficient(b, p);
      bool negative;
      if (!side_->Sign(coefficient, n, SignContext(b, p, node), &negative)) return false;
      state_[node] = negative ? 2 : 1;
      const auto& d = b.dims[0];
      const uint8_t neighbours = static_cast<uint8_t>((p[3] > 0) | (p[3] + 1 < d[3]) << 1 |
                                                      (p[2] > 0) << 2 | (p[2] + 1 < d[2]) << 3);
      lsp_.push_back({coefficient, node, bi, neighbours});
      return true;
    }
    state_[node] = 1;
    const int ck = k - 1;
    const auto& d = b.dims[ck];
    Coords lo, count;
    int total = 1;
    for (int a = 0; a < kAxes; ++a) {
      lo[a] = 2 * p[a];
      count[a] = std::min<uint32_t>(2, d[a] - lo[a]);
      total *= static_cast<int>(count[a]);
    }
    int index = 0, siblings = 0;
    Coords c;
    for (uint32_t i0 = 0; i0 < count[0]; ++i0)
      for (uint32_t i1 = 0; i1 < count[1]; ++i1)
        for (uint32_t i2 = 0; i2 < count[2]; ++i2)
          for (uint32_t i3 = 0; i3 < count[3]; ++i3, ++index) {
            c = {lo[0] + i0, lo[1] + i1, lo[2] + i2, lo[3] + i3};
            const uint32_t child = b.Node(ck, c);
            bool sig = true;  // the last child when none before it was significant
            if (index + 1 < total || siblings > 0) {
              const int ctx = SigContext(ctx4::kSigChild, b, ck, c, child, siblings);
              if (!side_->SigNode(child, n, ctx, &sig)) return false;
            }
            if (sig) {
              ++siblings;
              if (!Significant(bi, ck, c, child, n)) return false;
            } else {
              lin_[ck].push_back({child, bi});
            }
          }
    return true;
  }

  const QuadtreeLayout& layout_;
  const std::vector<QuadtreeBand>& bands_;
  Side* side_;
  uint8_t* state_ = nullptr;  // per node: 0 insignificant; 1 significant (coefficients:
                              // 1 positive, 2 negative)
  std::vector<std::vector<Entry>> lin_;
  std::vector<Leaf> lsp_;
};

}  // namespace fvv

#endif  // FVV_CODEC_QUADTREE4D_COMMON_H_
