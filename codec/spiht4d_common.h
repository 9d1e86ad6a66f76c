// 4D SPIHT: spatial-orientation trees over the 4D wavelet pyramid, and the one
// traversal both encoder and decoder run (so their decision order cannot drift).
//
// Tree (see wavelet.h for the geometry): a detail coefficient at global level
// l >= 2 has its children at level l - 1. Along each axis its position p is in
//   - the detail band of split l ("H"): children lo[l-1] + 2q, +1 (q = p - lo[l]),
//     and +2 as well for the last q when the finer band is one longer (odd sizes);
//   - the low part ("L", axis still split at l): children 2p, 2p + 1 (clipped);
//   - an axis not split at l ("U"): the child p, and also lo[l-1] + p when the
//     axis is split at l - 1 (its last split), which covers that detail band.
// The children are the product of the per-axis lists: up to 16, fewer where axes
// are exhausted or clipped. Roots (the final low band, "level L + 1") follow the
// same rule with every axis "U", minus the root itself: up to 15 children.
// Where axes run out of levels at different depths, a detail band whose every
// high-pass axis makes its last split at level l < L has no parent band at l + 1;
// its coefficients are tree tops too (listed after the roots, coarsest first).
//
// Traversal: classic SPIHT lists (LIP, LIS with type A/B entries, LSP), bitplanes
// from the top down, each a sorting pass then a refinement pass. Decisions carry
// a context so the arithmetic mode can model them; the binary mode ignores it.
#ifndef FVV_CODEC_SPIHT4D_COMMON_H_
#define FVV_CODEC_SPIHT4D_COMMON_H_

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "codec/subband_weights.h"
#include "codec/wavelet.h"

namespace fvv {

enum class EntropyCoder : uint8_t {
  kBinary = 0,  // decisions written as raw bits (as the original system)
  kArith = 1,   // context-adaptive binary range coding (format versions 1 to 3)
  // Format version 4: the same range coder with the neighbourhood contexts of
  // ctx2 below (significance of the coefficients at t - 1 and t + 1, of a set's
  // root and its neighbours, and of a refined coefficient's neighbours).
  kArith2 = 2,
};
constexpr int kEntropyCoders = 3;
const char* CoderName(EntropyCoder c);
inline bool RangeCoded(EntropyCoder c) { return c != EntropyCoder::kBinary; }

constexpr int kMaxChildren = 81;  // 3 per axis in the odd-size corner case
constexpr int kMaxBitplanes = 30;

// Where a SPIHT stream can be cut with a pass complete.
struct TruncationPoint {
  uint32_t bytes = 0;  // bytes a decoder needs to complete the pass
  uint8_t plane = 0;   // bitplane n of the pass
  uint8_t pass = 0;    // 0 = sorting, 1 = refinement
};

class SpihtTree {
 public:
  explicit SpihtTree(const WaveletGeometry& geometry);

  const WaveletGeometry& geometry() const { return g_; }
  const std::vector<uint32_t>& roots() const { return roots_; }
  size_t size() const { return g_.shape.count(); }

  void Coords(uint32_t idx, std::array<uint32_t, kAxes>* p) const {
    uint32_t q = idx;
    for (int a = kAxes - 1; a > 0; --a) {
      const uint32_t next = Divide(q, a);
      (*p)[a] = q - next * g_.shape.n[a];
      q = next;
    }
    (*p)[0] = q;
  }
  // 1..L for detail coefficients, L + 1 for roots.
  int Level(const std::array<uint32_t, kAxes>& p) const {
    int l = g_.levels + 1;
    for (int a = 0; a < kAxes; ++a) {
      const int b = g_.axis[a].band[p[a]];
      if (b != 0 && b < l) l = b;
    }
    return l;
  }
  int BandId(uint32_t idx) const {
    std::array<uint32_t, kAxes> p;
    Coords(idx, &p);
    std::array<uint8_t, kAxes> codes;
    for (int a = 0; a < kAxes; ++a) codes[a] = g_.axis[a].band[p[a]];
    return SubbandQuantisers::BandId(codes);
  }
  // Writes the children of idx to out; returns their number.
  int Children(uint32_t idx, uint32_t* out) const;
  // L(idx) (descendants beyond the children) is non-empty.
  bool HasGrandchildren(uint32_t idx) const;
  // Context class of a coefficient's level: 0 root, 1 level >= 4, 2 level 3,
  // 3 level 2, 4 level 1.
  int LevelClass(uint32_t idx) const { return position_[idx] & kClassMask; }
  // Which spatial neighbours exist (the context model's hot path asks for every
  // decision; a table saves the divisions of Coords).
  bool HasLeft(uint32_t idx) const { return position_[idx] & kLeft; }
  bool HasRight(uint32_t idx) const { return position_[idx] & kRight; }
  bool HasUp(uint32_t idx) const { return position_[idx] & kUp; }
  bool HasDown(uint32_t idx) const { return position_[idx] & kDown; }

 private:
  void AppendBox(const std::array<uint32_t, kAxes>& lo, const std::array<uint32_t, kAxes>& hi,
                 int level);

  static constexpr uint8_t kClassMask = 7, kLeft = 8, kRight = 16, kUp = 32, kDown = 64;
  void BuildPositionTable();
  // q / n[a] by a multiplication (Lemire, Kaser and Kurz, "Faster remainder by
  // direct computation", 2019): with M = ceil(2^64 / n), floor(M q / 2^64) is
  // exact for every 32-bit q. Coords runs for every set the traversal splits,
  // and a hardware division per axis was a tenth of its cost. M = 0 marks n = 1.
  uint32_t Divide(uint32_t q, int a) const {
    if (divide_magic_[a] == 0) return q;
    return static_cast<uint32_t>((static_cast<unsigned __int128>(divide_magic_[a]) * q) >> 64);
  }
  std::array<uint64_t, kAxes> divide_magic_{};

  WaveletGeometry g_;
  std::vector<uint32_t> roots_;    // tree tops: the root band, then parentless detail bands
  std::vector<uint8_t> position_;  // per coefficient: level class | neighbour flags
};

// The tree of a geometry, shared by every block of that shape: building one
// writes a byte per coefficient, which a decoder would otherwise repeat for each
// channel of each fragment. A few recent trees of moderate size are kept.
std::shared_ptr<const SpihtTree> SharedSpihtTree(const WaveletGeometry& geometry);

// Context indices of the adaptive model: ctx for coder 1 (arith), ctx2 for
// coder 2 (arith2).
namespace ctx {
constexpr int kLevelClasses = 5;
constexpr int kNeighbourBins = 3;
constexpr int kSigLip = 0;                                           // [class][nbr]
constexpr int kSigChild = kSigLip + kLevelClasses * kNeighbourBins;  // [sib][class][nbr]
constexpr int kSiblingBins = 3;                                      // significant siblings so far
constexpr int kSetA = kSigChild + kLevelClasses * kNeighbourBins * kSiblingBins;  // [class]
constexpr int kSetB = kSetA + kLevelClasses;                                      // [class]
constexpr int kSignStates = 9;  // (left, up) neighbour: insignificant, positive, negative
constexpr int kSign = kSetB + kLevelClasses;                  // [class][left][up]
constexpr int kRefine = kSign + kLevelClasses * kSignStates;  // [first?]
constexpr int kCount = kRefine + 2;
}  // namespace ctx

// Coder 2. On the demo capture's atlas textures most of its gain is in the set
// and refinement contexts; the temporal neighbours add a third of it (the
// textures change little from frame to frame, so a coefficient whose
// neighbour in time is significant is likely significant too).
namespace ctx2 {
constexpr int kLevelClasses = ctx::kLevelClasses;
constexpr int kSpatialBins = 3;   // significant of x - 1, x + 1, y - 1, y + 1, clipped to 2
constexpr int kTemporalBins = 3;  // significant of t - 1, t + 1
constexpr int kNeighbourBins = kSpatialBins * kTemporalBins;
constexpr int kSiblingBins = ctx::kSiblingBins;
constexpr int kSigLip = 0;  // [class][spatial][temporal]
constexpr int kSigChild =
    kSigLip + kLevelClasses * kNeighbourBins;  // [sib][class][spatial][temporal]
constexpr int kSetBins = 2 * kSpatialBins;     // root significant? x spatial
constexpr int kSetA =
    kSigChild + kSiblingBins * kLevelClasses * kNeighbourBins;     // [class][root][spatial]
constexpr int kSetB = kSetA + kLevelClasses * kSetBins;            // [class][root][spatial]
constexpr int kSign = kSetB + kLevelClasses * kSetBins;            // [class][left][up], as ctx
constexpr int kRefine = kSign + kLevelClasses * ctx::kSignStates;  // [first?][spatial]
constexpr int kCount = kRefine + 2 * kSpatialBins;
}  // namespace ctx2
constexpr int kMaxContexts = ctx2::kCount > ctx::kCount ? ctx2::kCount : ctx::kCount;

// The traversal. Side provides (each returns false to stop the traversal now):
//   bool SigCoeff(uint32_t idx, int n, int ctx, bool* sig);
//   bool Sign(uint32_t idx, int n, int ctx, bool* negative);
//   bool SigSet(uint32_t idx, int n, bool type_b, int ctx, bool* sig);
//   bool Refine(uint32_t idx, int n, int ctx);
//   void PassEnd(int n, int pass);
// kNeighbourhood selects the contexts: false ctx (coders 0 and 1), true ctx2 (coder 2).
template <bool kNeighbourhood, class Side>
void SpihtTraverse(const SpihtTree& tree, int planes, Side* side) {
  const Shape4D& shape = tree.geometry().shape;
  const uint32_t w = shape.width();
  // Neighbours in time: one frame apart in the block's layout.
  const size_t frame = size_t(shape.n[1]) * shape.n[2] * shape.n[3];
  const size_t count = shape.count();
  // 0: not (yet) significant; 1: significant, positive; 2: significant, negative.
  // Kept per thread: a fresh multi-megabyte array per channel costs page faults.
  // It is all zero between traversals (each clears the entries it set, below),
  // so none has to clear the whole array first.
  thread_local std::vector<uint8_t> significant;
  if (significant.size() < tree.size()) significant.resize(tree.size());
  // Significant spatial neighbours (x +- 1, y +- 1), clipped to 2: the context.
  auto neighbours = [&](uint32_t idx) {
    int k = 0;
    if (tree.HasLeft(idx)) k += significant[idx - 1] != 0;
    if (tree.HasRight(idx)) k += significant[idx + 1] != 0;
    if (tree.HasUp(idx)) k += significant[idx - w] != 0;
    if (tree.HasDown(idx)) k += significant[idx + w] != 0;
    return k < 2 ? k : 2;
  };
  auto temporal = [&](uint32_t idx) {
    int k = 0;
    if (idx >= frame) k += significant[idx - frame] != 0;
    if (idx + frame < count) k += significant[idx + frame] != 0;
    return k;
  };
  // Signs of the left and upper neighbours: signs of neighbouring wavelet
  // coefficients are correlated along edges.
  auto sign_ctx = [&](uint32_t idx) {
    const int left = tree.HasLeft(idx) ? significant[idx - 1] : 0;
    const int up = tree.HasUp(idx) ? significant[idx - w] : 0;
    return (kNeighbourhood ? ctx2::kSign : ctx::kSign) + tree.LevelClass(idx) * ctx::kSignStates +
           left * 3 + up;
  };
  std::vector<uint32_t> lsp;
  // On every way out: the LSP holds every coefficient marked significant.
  struct ClearSignificant {
    std::vector<uint8_t>& flags;
    const std::vector<uint32_t>& marked;
    ~ClearSignificant() {
      for (uint32_t idx : marked) flags[idx] = 0;
    }
  } clear_on_exit{significant, lsp};
  // A newly significant coefficient's sign; it joins the LSP (before it is
  // marked, so that the clearing above always covers the marks).
  auto code_sign = [&](uint32_t idx, int n) {
    bool negative;
    if (!side->Sign(idx, n, sign_ctx(idx), &negative)) return false;
    lsp.push_back(idx);
    significant[idx] = negative ? 2 : 1;
    return true;
  };
  // base: the context group's first index (for a child, of its sibling bin).
  auto coeff_ctx = [&](int base, uint32_t idx) {
    if (kNeighbourhood) {
      return base + tree.LevelClass(idx) * ctx2::kNeighbourBins +
             neighbours(idx) * ctx2::kTemporalBins + temporal(idx);
    }
    return base + tree.LevelClass(idx) * ctx::kNeighbourBins + neighbours(idx);
  };
  auto set_ctx = [&](uint32_t idx, bool type_b) {
    const int cls = tree.LevelClass(idx);
    if (kNeighbourhood) {
      return (type_b ? ctx2::kSetB : ctx2::kSetA) + cls * ctx2::kSetBins +
             (significant[idx] != 0) * ctx2::kSpatialBins + neighbours(idx);
    }
    return (type_b ? ctx::kSetB : ctx::kSetA) + cls;
  };
  auto refine_ctx = [&](uint32_t idx, bool first) {
    if (kNeighbourhood) return ctx2::kRefine + first * ctx2::kSpatialBins + neighbours(idx);
    return ctx::kRefine + (first ? 1 : 0);
  };
  const int sig_lip = kNeighbourhood ? ctx2::kSigLip : ctx::kSigLip;
  const int sig_child = kNeighbourhood ? ctx2::kSigChild : ctx::kSigChild;
  const int sibling_stride = kNeighbourhood ? ctx2::kLevelClasses * ctx2::kNeighbourBins
                                            : ctx::kLevelClasses * ctx::kNeighbourBins;

  std::vector<uint32_t> lip = tree.roots();
  std::vector<uint32_t> lis;
  constexpr uint32_t kTypeB = 0x80000000u;
  uint32_t children[kMaxChildren];
  for (uint32_t r : tree.roots())
    if (tree.Children(r, children) > 0) lis.push_back(r);

  size_t lsp_first_refine = 0;  // LSP entries before this index had >= 1 refinement
  for (int n = planes - 1; n >= 0; --n) {
    const size_t lsp_before_pass = lsp.size();
    // Sorting pass, part 1: insignificant pixels.
    size_t kept = 0;
    for (size_t i = 0; i < lip.size(); ++i) {
      const uint32_t idx = lip[i];
      bool sig;
      if (!side->SigCoeff(idx, n, coeff_ctx(sig_lip, idx), &sig)) return;
      if (sig) {
        if (!code_sign(idx, n)) return;
      } else {
        lip[kept++] = idx;
      }
    }
    lip.resize(kept);
    // Sorting pass, part 2: insignificant sets; entries appended here are
    // processed in this same pass.
    kept = 0;
    for (size_t i = 0; i < lis.size(); ++i) {
      const uint32_t entry = lis[i];
      const uint32_t idx = entry & ~kTypeB;
      const bool type_b = (entry & kTypeB) != 0;
      bool sig;
      if (!side->SigSet(idx, n, type_b, set_ctx(idx, type_b), &sig)) return;
      if (!sig) {
        lis[kept++] = entry;
        continue;
      }
      const int nc = tree.Children(idx, children);
      if (!type_b) {
        int siblings = 0;
        for (int k = 0; k < nc; ++k) {
          const uint32_t c = children[k];
          bool csig;
          const int sib = siblings < ctx::kSiblingBins ? siblings : ctx::kSiblingBins - 1;
          const int base = sig_child + sib * sibling_stride;
          if (!side->SigCoeff(c, n, coeff_ctx(base, c), &csig)) return;
          siblings += csig;
          if (csig) {
            if (!code_sign(c, n)) return;
          } else {
            lip.push_back(c);
          }
        }
        if (tree.HasGrandchildren(idx)) lis.push_back(idx | kTypeB);
      } else {
        for (int k = 0; k < nc; ++k) lis.push_back(children[k]);
      }
    }
    lis.resize(kept);
    side->PassEnd(n, 0);
    // Refinement pass over coefficients significant before this bitplane.
    for (size_t i = 0; i < lsp_before_pass; ++i)
      if (!side->Refine(lsp[i], n, refine_ctx(lsp[i], i >= lsp_first_refine))) return;
    lsp_first_refine = lsp_before_pass;
    side->PassEnd(n, 1);
  }
}

// The traversal with the contexts of `coder` (chosen once, outside the hot path).
template <class Side>
void SpihtTraverse(EntropyCoder coder, const SpihtTree& tree, int planes, Side* side) {
  if (coder == EntropyCoder::kArith2) {
    SpihtTraverse<true>(tree, planes, side);
  } else {
    SpihtTraverse<false>(tree, planes, side);
  }
}

}  // namespace fvv

#endif  // FVV_CODEC_SPIHT4D_COMMON_H_
