// The BISK traversal both the encoder and the decoder run (codec/bisk.h):
// internal to the codec.
#ifndef FVV_CODEC_BISK_COMMON_H_
#define FVV_CODEC_BISK_COMMON_H_

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "codec/range_coder.h"

namespace fvv {
namespace bisk {

struct Set {
  uint32_t x = 0, y = 0, w = 0, h = 0;
  uint8_t across_x = 1;  // the next split halves x (else y)
  uint8_t level = 0;     // subband level (0 = the coarsest band), for contexts
};

// Context layout.
constexpr int kSetContexts = 24;      // by log2 of the set's area
constexpr int kCoefContexts = 2 * 8;  // by level, neighbour significant
constexpr int kCtxSet = 0;
constexpr int kCtxCoef = kCtxSet + kSetContexts;
constexpr int kCtxSign = kCtxCoef + kCoefContexts;
constexpr int kCtxRefine = kCtxSign + 1;  // first refinement, later ones
constexpr int kContexts = kCtxRefine + 2;

inline uint32_t Extent(uint32_t n, int level) {
  for (int l = 0; l < level; ++l) n = (n + 1) / 2;
  return n;
}

// Bits coefficient (x, y) is scaled up by before coding, so that a bit of
// any coefficient is worth about the same squared error: the lifting kernels
// leave the low band's gain at 1 and the high band's at about 2 per split, so
// a coarse coefficient's error spreads over more samples. Relative weights of
// an orthonormal transform, in whole bits: LL of L levels 2^(L+1), HL and LH
// of level l 2^l, HH of level l 2^(l-1).
inline int SubbandShift(uint32_t x, uint32_t y, uint32_t width, uint32_t height, int levels) {
  for (int l = 1; l <= levels; ++l) {
    const uint32_t wl = Extent(width, l), hl = Extent(height, l);
    const bool high_x = x >= wl, high_y = y >= hl;
    if (high_x || high_y) return high_x && high_y ? l - 1 : l;
  }
  return levels + 1;
}

// SubbandShift for a whole plane at O(1) per coefficient: per column the
// first level whose high band holds it (levels + 1: none), likewise per row.
class SubbandShifts {
 public:
  SubbandShifts(uint32_t width, uint32_t height, int levels)
      : levels_(levels), lx_(First(width, levels)), ly_(First(height, levels)) {}
  int operator()(uint32_t x, uint32_t y) const {
    const int lx = lx_[x], ly = ly_[y];
    if (lx > levels_ && ly > levels_) return levels_ + 1;
    return lx == ly ? lx - 1 : std::min(lx, ly);
  }

 private:
  static std::vector<uint8_t> First(uint32_t n, int levels) {
    std::vector<uint8_t> out(n, uint8_t(levels + 1));
    for (int l = levels; l >= 1; --l) {
      for (uint32_t i = Extent(n, l); i < n; ++i) out[i] = uint8_t(l);
    }
    return out;
  }
  int levels_;
  std::vector<uint8_t> lx_, ly_;
};

inline int Log2Floor(uint64_t v) {
  int l = 0;
  while (v > 1) v >>= 1, ++l;
  return l;
}

// The traversal both sides run; `kEncode` picks whether decisions are written
// (from the coefficients) or read (into them).
template <bool kEncode>
class BiskCoder {
 public:
  BiskCoder(uint32_t width, uint32_t height, const std::vector<uint8_t>& layout, int levels,
            int32_t* coefficients, RangeEncoder* enc, RangeDecoder* dec)
      : w_(width),
        h_(height),
        layout_(layout),
        levels_(levels),
        c_(coefficients),
        enc_(enc),
        dec_(dec),
        probs_(kContexts, kProbInit),
        significant_(size_t(width) * height, 0),
        joined_(significant_.size(), 0),
        low_(significant_.size(), 0) {
    if (!kEncode)
      magnitude_.assign(significant_.size(), 0), negative_.assign(significant_.size(), 0);
    const size_t stride = size_t(width) + 1;
    sat_.assign(stride * (size_t(height) + 1), 0);
    for (uint32_t y = 0; y < height; ++y) {
      uint32_t row = 0;
      for (uint32_t x = 0; x < width; ++x) {
        row += layout_[size_t(y) * width + x] ? 1 : 0;
        sat_[(y + 1) * stride + x + 1] = sat_[y * stride + x + 1] + row;
      }
    }
  }

  // Codes planes top..0; returns the whole planes completed.
  int Run(int top) {
    // The subbands, coarsest first.
    const auto add = [&](uint32_t x0, uint32_t y0, uint32_t x1, uint32_t y1, int level) {
      Set s;
      s.x = x0, s.y = y0, s.w = x1 - x0, s.h = y1 - y0, s.level = uint8_t(level);
      if (Shrink(&s)) lis_.push_back(s);
    };
    add(0, 0, Extent(w_, levels_), Extent(h_, levels_), 0);
    for (int l = levels_; l >= 1; --l) {
      const uint32_t wl = Extent(w_, l), hl = Extent(h_, l), wp = Extent(w_, l - 1),
                     hp = Extent(h_, l - 1);
      const int band = levels_ - l + 1;
      add(wl, 0, wp, hl, band);
      add(0, hl, wl, hp, band);
      add(wl, hl, wp, hp, band);
    }
    int completed = 0;
    for (int n = top; n >= 0; --n) {
      plane_ = n;
      std::vector<Set> next;
      const size_t old_lsp = lsp_.size();
      for (const Set& s : lis_) {
        if (!Process(s, false, &next)) return completed;
      }
      lis_.swap(next);
      for (size_t i = 0; i < old_lsp; ++i) {
        const uint32_t at = lsp_[i];
        uint32_t bit = kEncode ? (uint32_t(std::abs(c_[at])) >> n) & 1u : 0;
        // First refinement (joined in the plane above) or a later one.
        const int ctx = kCtxRefine + (joined_[at] == n + 2 ? 0 : 1);
        if (!Code(ctx, &bit)) return completed;
        if (!kEncode) magnitude_[at] |= bit << n;
        low_[at] = uint8_t(n);
      }
      ++completed;
      if (kEncode && plane_ends_) plane_ends_->push_back(size_t(enc_->BytesNeeded()));
    }
    return completed;
  }
  // Encoder: where each completed plane ends in the range coder's bytes.
  void set_plane_ends(std::vector<size_t>* ends) { plane_ends_ = ends; }

  // Decoder: each significant coefficient at the middle of the interval its
  // known bits leave (its lowest known bit: the plane it joined in or was
  // last refined in).
  void Reconstruct() const {
    for (size_t i = 0; i < significant_.size(); ++i) {
      if (!significant_[i]) {
        c_[i] = 0;
        continue;
      }
      int32_t mag = int32_t(magnitude_[i]);
      if (low_[i] > 0) mag += int32_t(1) << (low_[i] - 1);
      c_[i] = negative_[i] ? -mag : mag;
    }
  }

 private:
  bool Code(int ctx, uint32_t* bit) {
    if (kEncode) {
      enc_->Encode(*bit, &probs_[ctx]);
      return true;
    }
    if (!dec_->ok()) return false;
    *bit = dec_->Decode(&probs_[ctx]);
    return true;
  }

  // Shrinks to the bounding box of in-shape coefficients; false if none.
  // Each side by bisection over the summed-area table: O(log) per side, not
  // a scan of the set (which made shrinking most of the coder's time).
  bool Shrink(Set* s) const {
    const uint32_t xs = s->x, ys = s->y, xe = s->x + s->w, ye = s->y + s->h;
    const uint32_t total = Count(xs, ys, xe, ye);
    if (total == 0) return false;
    const uint32_t y0 =
        SmallestEnd(ys, ye, [&](uint32_t e) { return Count(xs, ys, xe, e) > 0; }) - 1;
    const uint32_t y1 =
        SmallestEnd(ys, ye, [&](uint32_t e) { return Count(xs, ys, xe, e) == total; });
    const uint32_t x0 =
        SmallestEnd(xs, xe, [&](uint32_t e) { return Count(xs, y0, e, y1) > 0; }) - 1;
    const uint32_t x1 =
        SmallestEnd(xs, xe, [&](uint32_t e) { return Count(xs, y0, e, y1) == total; });
    s->x = x0, s->y = y0, s->w = x1 - x0, s->h = y1 - y0;
    return true;
  }

  // The smallest e in (lo, hi] with pred(e), for pred false then true, true at hi.
  template <typename Pred>
  static uint32_t SmallestEnd(uint32_t lo, uint32_t hi, const Pred& pred) {
    while (hi - lo > 1) {
      const uint32_t mid = lo + (hi - lo) / 2;
      if (pred(mid)) {
        hi = mid;
      } else {
        lo = mid;
      }
    }
    return hi;
  }

  // Layout positions in [x0, x1) x [y0, y1), from the summed-area table.
  uint32_t Count(uint32_t x0, uint32_t y0, uint32_t x1, uint32_t y1) const {
    const size_t stride = size_t(w_) + 1;
    return sat_[y1 * stride + x1] - sat_[y0 * stride + x1] - sat_[y1 * stride + x0] +
           sat_[y0 * stride + x0];
  }

  bool SetSignificant(const Set& s) const {
    const int32_t t = int32_t(1) << plane_;
    for (uint32_t y = s.y; y < s.y + s.h; ++y) {
      for (uint32_t x = s.x; x < s.x + s.w; ++x) {
        const size_t i = size_t(y) * w_ + x;
        if (layout_[i] && !significant_[i] && std::abs(c_[i]) >= t) return true;
      }
    }
    return false;
  }

  // Tests set `s` at the current plane; splits it when significant. Sets
  // left insignificant go to `out`. False once the decoder ran out of bytes.
  bool Process(const Set& s, bool known_significant, std::vector<Set>* out) {
    if (s.w == 1 && s.h == 1) {
      const size_t i = size_t(s.y) * w_ + s.x;
      uint32_t sig = 1;
      if (!known_significant) {
        sig = kEncode ? uint32_t(std::abs(c_[i]) >= (int32_t(1) << plane_)) : 0;
        const bool neighbour =
            (s.x > 0 && significant_[i - 1]) || (s.y > 0 && significant_[i - w_]);
        if (!Code(kCtxCoef + 2 * std::min<int>(s.level, 7) + neighbour, &sig)) return false;
      }
      if (!sig) {
        out->push_back(s);
        return true;
      }
      uint32_t negative = kEncode ? uint32_t(c_[i] < 0) : 0;
      if (!Code(kCtxSign, &negative)) return false;
      significant_[i] = 1;
      joined_[i] = uint8_t(plane_ + 1);
      low_[i] = uint8_t(plane_);
      if (!kEncode) {
        magnitude_[i] = uint32_t(1) << plane_;
        negative_[i] = uint8_t(negative);
      }
      lsp_.push_back(uint32_t(i));
      return true;
    }
    uint32_t sig = 1;
    if (!known_significant) {
      sig = kEncode ? uint32_t(SetSignificant(s)) : 0;
      const int ctx = kCtxSet + std::min(Log2Floor(uint64_t(s.w) * s.h), kSetContexts - 1);
      if (!Code(ctx, &sig)) return false;
    }
    if (!sig) {
      out->push_back(s);
      return true;
    }
    // Halve across x or y (alternating; a side of 1 cannot be halved).
    const bool across_x = (s.across_x && s.w > 1) || s.h == 1;
    Set a = s, b = s;
    a.across_x = b.across_x = uint8_t(!across_x);
    if (across_x) {
      a.w = (s.w + 1) / 2;
      b.x = s.x + a.w, b.w = s.w - a.w;
    } else {
      a.h = (s.h + 1) / 2;
      b.y = s.y + a.h, b.h = s.h - a.h;
    }
    const bool has_a = Shrink(&a), has_b = Shrink(&b);
    if (has_a && has_b) {
      const size_t lsp_before = lsp_.size();
      if (!Process(a, false, out)) return false;
      // A significant half always adds a coefficient to the significant list;
      // when the first did not, the second must be significant.
      const bool a_insignificant = lsp_.size() == lsp_before;
      return Process(b, a_insignificant, out);
    }
    return Process(has_a ? a : b, true, out);
  }

  uint32_t w_, h_;
  const std::vector<uint8_t>& layout_;
  int levels_;
  int32_t* c_;
  RangeEncoder* enc_;
  RangeDecoder* dec_;
  std::vector<uint16_t> probs_;
  std::vector<uint32_t> sat_;  // summed-area table of the layout, (w + 1) x (h + 1)
  std::vector<uint8_t> significant_;
  std::vector<uint8_t> joined_;  // 1 + the plane a coefficient became significant in
  std::vector<uint8_t> low_;     // its lowest known bit plane
  std::vector<uint32_t> magnitude_;
  std::vector<uint8_t> negative_;
  std::vector<Set> lis_;
  std::vector<uint32_t> lsp_;
  std::vector<size_t>* plane_ends_ = nullptr;
  int plane_ = 0;
};

}  // namespace bisk
}  // namespace fvv

#endif  // FVV_CODEC_BISK_COMMON_H_
