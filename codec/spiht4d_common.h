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

#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "codec/quadtree4d_common.h"
#include "codec/subband_weights.h"
#include "codec/wavelet.h"

namespace fvv {

enum class EntropyCoder : uint8_t {
  kBinary = 0,  // decisions written as raw bits (as the original system)
  kArith = 1,   // context-adaptive binary range coding (format versions 1 to 3)
  // Format version 4: the same range coder with the neighbourhood contexts of
  // ctx2 below (significance of the coefficients at t - 1 and t + 1, of a set's
  // root and its neighbours, and of a refined coefficient's neighbours).
  kNeighbourContexts = 2,
  // Format version 5: ctx3 below (a set's significance also on its root's
  // magnitude and on the sets of its neighbours in space and time, a sign on
  // the signs of four spatial and two temporal neighbours) with probabilities
  // that adapt fast while a context is young (mixing::Update).
  kSetSignContexts = 3,
  // Format version 8: not SPIHT's sets but a quadtree per subband
  // (codec/quadtree4d_common.h), with coder 3's count-adaptive probabilities.
  kQuadtree = 4,
};
constexpr int kEntropyCoders = 5;
const char* CoderName(EntropyCoder c);
inline bool RangeCoded(EntropyCoder c) { return c != EntropyCoder::kBinary; }
// Probabilities that adapt fast while a context is young (mixing::Update).
inline bool CountAdaptive(EntropyCoder c) {
  return c == EntropyCoder::kSetSignContexts || c == EntropyCoder::kQuadtree;
}

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

// Coder 3: ctx2's coefficient significance and refinement contexts, new set and
// sign contexts. A set's significance is the least predictable decision of
// coder 2 (0.87 bits per decision on the Kodak images at 0.25 bpp) and a
// quarter of the bits; what predicts it is how large its root is and whether
// the sets next to it, in space and time, were significant.
namespace ctx3 {
constexpr int kLevelClasses = ctx::kLevelClasses;
constexpr int kSigLip = ctx2::kSigLip;      // as ctx2
constexpr int kSigChild = ctx2::kSigChild;  // as ctx2
// A type A set: its root insignificant, significant since plane n or n + 1, or
// earlier; significant D sets at x - 1, x + 1, y - 1, y + 1 (clipped to 2); a
// significant D set at t - 1 or t + 1.
constexpr int kRootBins = 3;
constexpr int kSetSpatialBins = 3;
constexpr int kSetTemporalBins = 2;
constexpr int kSetA = ctx2::kSetA;  // [class][root][set spatial][set temporal]
// A type B set: its significant children (clipped to 2); a neighbour's D set significant.
constexpr int kChildBins = 3;
constexpr int kSetB = kSetA + kLevelClasses * kRootBins * kSetSpatialBins * kSetTemporalBins;
// A sign: the sums of the signs of the horizontal, vertical and temporal
// neighbour pairs, each zero, positive or negative.
constexpr int kSignBins = 3;
constexpr int kSign = kSetB + kLevelClasses * kChildBins * 2;  // [class][child][neighbour set]
constexpr int kRefine =
    kSign + kLevelClasses * kSignBins * kSignBins * kSignBins;  // [class][h][v][t]
constexpr int kCount = kRefine + 2 * ctx2::kSpatialBins;        // refine as ctx2
}  // namespace ctx3
constexpr int kMaxContexts = std::max({ctx::kCount, ctx2::kCount, ctx3::kCount, ctx4::kCount});

// Which context set a coder uses (the traversal's template argument).
enum class ContextSet { kLevel = 1, kNeighbourhood = 2, kSets = 3 };

// The traversal. Side provides (each returns false to stop the traversal now):
//   bool SigCoeff(uint32_t idx, int n, int ctx, bool* sig);
//   bool Sign(uint32_t idx, int n, int ctx, bool* negative);
//   bool SigSet(uint32_t idx, int n, bool type_b, int ctx, bool* sig);
//   bool Refine(uint32_t idx, int n, int ctx);
//   void PassEnd(int n, int pass);
// kSet selects the contexts: kLevel ctx (coders 0 and 1), kNeighbourhood ctx2
// (coder 2), kSets ctx3 (coder 3).
template <ContextSet kSet, class Side>
void SpihtTraverse(const SpihtTree& tree, int planes, Side* side) {
  constexpr bool kCtx1 = kSet == ContextSet::kLevel;
  constexpr bool kCtx3 = kSet == ContextSet::kSets;
  const Shape4D& shape = tree.geometry().shape;
  const uint32_t w = shape.width();
  // Neighbours in time: one frame apart in the block's layout.
  const size_t frame = size_t(shape.n[1]) * shape.n[2] * shape.n[3];
  const size_t count = shape.count();
  // Per coefficient: bits 0-1 0 = not (yet) significant, 1 = significant and
  // positive, 2 = significant and negative; for ctx3 also bits 2-6 the plane
  // in which it became significant and bit 7 "its set D is significant".
  // Kept per thread: a fresh multi-megabyte array per channel costs page faults.
  // It is all zero between traversals (each clears the entries it set, below),
  // so none has to clear the whole array first.
  constexpr uint8_t kSignBits = 3, kSetSignificant = 0x80;
  constexpr int kPlaneShift = 2;
  thread_local std::vector<uint8_t> state;
  if (state.size() < tree.size()) state.resize(tree.size());
  auto significant = [&](size_t idx) { return (state[idx] & kSignBits) != 0; };
  // Spatial neighbours (x +- 1, y +- 1) with any of `flags` set, clipped to 2.
  auto count_neighbours = [&](uint32_t idx, uint8_t flags) {
    int k = 0;
    if (tree.HasLeft(idx)) k += (state[idx - 1] & flags) != 0;
    if (tree.HasRight(idx)) k += (state[idx + 1] & flags) != 0;
    if (tree.HasUp(idx)) k += (state[idx - w] & flags) != 0;
    if (tree.HasDown(idx)) k += (state[idx + w] & flags) != 0;
    return k < 2 ? k : 2;
  };
  // Significant spatial neighbours: the context.
  auto neighbours = [&](uint32_t idx) { return count_neighbours(idx, kSignBits); };
  auto temporal = [&](uint32_t idx) {
    int k = 0;
    if (idx >= frame) k += significant(idx - frame);
    if (idx + frame < count) k += significant(idx + frame);
    return k;
  };
  // Signs of neighbours: signs of neighbouring wavelet coefficients are
  // correlated along edges (and, in atlas textures, in time). ctx and ctx2 look
  // at the left and upper neighbour; ctx3 at the sums of the signs of the
  // horizontal, vertical and temporal pairs.
  auto sign_of = [&](size_t idx) {
    const int s = state[idx] & kSignBits;
    return s == 0 ? 0 : s == 1 ? 1 : -1;
  };
  auto sign_bin = [](int sum) { return sum > 0 ? 1 : sum < 0 ? 2 : 0; };
  auto sign_ctx = [&](uint32_t idx) {
    const int cls = tree.LevelClass(idx);
    if (kCtx3) {
      int h = 0, v = 0, t = 0;
      if (tree.HasLeft(idx)) h += sign_of(idx - 1);
      if (tree.HasRight(idx)) h += sign_of(idx + 1);
      if (tree.HasUp(idx)) v += sign_of(idx - w);
      if (tree.HasDown(idx)) v += sign_of(idx + w);
      if (idx >= frame) t += sign_of(idx - frame);
      if (idx + frame < count) t += sign_of(idx + frame);
      return ctx3::kSign +
             ((cls * ctx3::kSignBins + sign_bin(h)) * ctx3::kSignBins + sign_bin(v)) *
                 ctx3::kSignBins +
             sign_bin(t);
    }
    const int left = tree.HasLeft(idx) ? state[idx - 1] & kSignBits : 0;
    const int up = tree.HasUp(idx) ? state[idx - w] & kSignBits : 0;
    return (kCtx1 ? ctx::kSign : ctx2::kSign) + cls * ctx::kSignStates + left * 3 + up;
  };
  std::vector<uint32_t> lsp;
  std::vector<uint32_t> sets_marked;  // ctx3: coefficients whose D set was found significant
  // On every way out: the LSP and sets_marked hold every coefficient with state.
  struct ClearState {
    std::vector<uint8_t>& flags;
    const std::vector<uint32_t>& marked;
    const std::vector<uint32_t>& marked_sets;
    ~ClearState() {
      for (uint32_t idx : marked) flags[idx] = 0;
      for (uint32_t idx : marked_sets) flags[idx] = 0;
    }
  } clear_on_exit{state, lsp, sets_marked};
  // A newly significant coefficient's sign; it joins the LSP (before it is
  // marked, so that the clearing above always covers the marks).
  auto code_sign = [&](uint32_t idx, int n) {
    bool negative;
    if (!side->Sign(idx, n, sign_ctx(idx), &negative)) return false;
    lsp.push_back(idx);
    state[idx] = static_cast<uint8_t>((state[idx] & kSetSignificant) | (n << kPlaneShift) |
                                      (negative ? 2 : 1));
    return true;
  };
  // base: the context group's first index (for a child, of its sibling bin).
  auto coeff_ctx = [&](int base, uint32_t idx) {
    if (kCtx1) return base + tree.LevelClass(idx) * ctx::kNeighbourBins + neighbours(idx);
    return base + tree.LevelClass(idx) * ctx2::kNeighbourBins +
           neighbours(idx) * ctx2::kTemporalBins + temporal(idx);
  };
  // ctx3: significant D sets among the spatial neighbours (clipped to 2) and in time.
  auto set_significant = [&](size_t idx) { return (state[idx] & kSetSignificant) != 0; };
  auto neighbour_sets = [&](uint32_t idx) { return count_neighbours(idx, kSetSignificant); };
  auto temporal_sets = [&](uint32_t idx) {
    return (idx >= frame && set_significant(idx - frame)) ||
           (idx + frame < count && set_significant(idx + frame));
  };
  uint32_t children[kMaxChildren];
  auto set_ctx = [&](uint32_t idx, bool type_b, int n) {
    const int cls = tree.LevelClass(idx);
    if (kCtx1) return (type_b ? ctx::kSetB : ctx::kSetA) + cls;
    if (!kCtx3) {
      return (type_b ? ctx2::kSetB : ctx2::kSetA) + cls * ctx2::kSetBins +
             significant(idx) * ctx2::kSpatialBins + neighbours(idx);
    }
    if (type_b) {
      const int nc = tree.Children(idx, children);
      int k = 0;
      for (int i = 0; i < nc && k < 2; ++i) k += significant(children[i]);
      return ctx3::kSetB + (cls * ctx3::kChildBins + k) * 2 + (neighbour_sets(idx) != 0);
    }
    // The root's magnitude: 0 insignificant, 1 below 2^(n + 2), 2 at least 2^(n + 2).
    const int root = !significant(idx) ? 0 : (state[idx] >> kPlaneShift & 0x1F) >= n + 2 ? 2 : 1;
    return ctx3::kSetA +
           ((cls * ctx3::kRootBins + root) * ctx3::kSetSpatialBins + neighbour_sets(idx)) *
               ctx3::kSetTemporalBins +
           temporal_sets(idx);
  };
  auto refine_ctx = [&](uint32_t idx, bool first) {
    if (kCtx1) return ctx::kRefine + (first ? 1 : 0);
    return (kCtx3 ? ctx3::kRefine : ctx2::kRefine) + first * ctx2::kSpatialBins + neighbours(idx);
  };
  const int sig_lip = kCtx1 ? ctx::kSigLip : ctx2::kSigLip;
  const int sig_child = kCtx1 ? ctx::kSigChild : ctx2::kSigChild;
  const int sibling_stride =
      kCtx1 ? ctx::kLevelClasses * ctx::kNeighbourBins : ctx2::kLevelClasses * ctx2::kNeighbourBins;

  std::vector<uint32_t> lip = tree.roots();
  std::vector<uint32_t> lis;
  constexpr uint32_t kTypeB = 0x80000000u;
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
      if (!side->SigSet(idx, n, type_b, set_ctx(idx, type_b, n), &sig)) return;
      if (!sig) {
        lis[kept++] = entry;
        continue;
      }
      const int nc = tree.Children(idx, children);
      if (!type_b) {
        if (kCtx3) {
          sets_marked.push_back(idx);  // before marking: the clearing covers it
          state[idx] |= kSetSignificant;
        }
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
  switch (coder) {
    case EntropyCoder::kSetSignContexts:
      SpihtTraverse<ContextSet::kSets>(tree, planes, side);
      break;
    case EntropyCoder::kNeighbourContexts:
      SpihtTraverse<ContextSet::kNeighbourhood>(tree, planes, side);
      break;
    default:
      SpihtTraverse<ContextSet::kLevel>(tree, planes, side);
  }
}

}  // namespace fvv

#endif  // FVV_CODEC_SPIHT4D_COMMON_H_
