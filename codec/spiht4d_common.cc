#include "codec/spiht4d_common.h"

#include <algorithm>
#include <mutex>
#include <vector>

namespace fvv {

const char* CoderName(EntropyCoder c) {
  switch (c) {
    case EntropyCoder::kQuadtree:
      return "arith4";
    case EntropyCoder::kSetSignContexts:
      return "arith3";
    case EntropyCoder::kNeighbourContexts:
      return "arith2";
    case EntropyCoder::kArith:
      return "arith";
    default:
      return "binary";
  }
}

SpihtTree::SpihtTree(const WaveletGeometry& geometry) : g_(geometry) {
  for (int a = 0; a < kAxes; ++a)
    divide_magic_[a] = g_.shape.n[a] > 1 ? ~uint64_t{0} / g_.shape.n[a] + 1 : 0;
  BuildPositionTable();
  // Tree tops, in order: the final low band R(L), then for l = L - 1 down to 1 the
  // detail coefficients of level l that have no parent: those whose every
  // high-pass axis makes its last split at l (so level l + 1 has no detail band of
  // that orientation). Each group in raster order.
  std::array<uint32_t, kAxes> lo_box, hi_box;
  for (int a = 0; a < kAxes; ++a) {
    lo_box[a] = 0;
    hi_box[a] = g_.RegionExtent(a, g_.levels);
  }
  AppendBox(lo_box, hi_box, -1);
  for (int l = g_.levels - 1; l >= 1; --l) {
    bool any = false;
    for (int a = 0; a < kAxes; ++a) {
      const AxisGeometry& ax = g_.axis[a];
      if (ax.levels == l) {
        hi_box[a] = ax.lo[l - 1];  // low and high part of its last split
        any = true;
      } else if (ax.levels > l) {
        hi_box[a] = ax.lo[l];  // low part only
      } else {
        hi_box[a] = ax.lo[ax.levels];
      }
    }
    if (any) AppendBox(lo_box, hi_box, l);
  }
}

void SpihtTree::AppendBox(const std::array<uint32_t, kAxes>& lo,
                          const std::array<uint32_t, kAxes>& hi, int level) {
  std::array<uint32_t, kAxes> p;
  for (p[0] = lo[0]; p[0] < hi[0]; ++p[0])
    for (p[1] = lo[1]; p[1] < hi[1]; ++p[1])
      for (p[2] = lo[2]; p[2] < hi[2]; ++p[2])
        for (p[3] = lo[3]; p[3] < hi[3]; ++p[3]) {
          if (level >= 0 && Level(p) != level) continue;  // the low part of the box is coarser
          roots_.push_back(static_cast<uint32_t>(g_.shape.Index(p[0], p[1], p[2], p[3])));
        }
}

int SpihtTree::Children(uint32_t idx, uint32_t* out) const {
  std::array<uint32_t, kAxes> p;
  Coords(idx, &p);
  const int l = Level(p);
  if (l == 1 || g_.levels == 0) return 0;
  std::array<std::array<uint32_t, 3>, kAxes> list;
  std::array<int, kAxes> count;
  const bool root = l == g_.levels + 1;
  for (int a = 0; a < kAxes; ++a) {
    const AxisGeometry& ax = g_.axis[a];
    const uint32_t pa = p[a];
    int k = 0;
    if (l > ax.levels) {
      // Axis not split at this level ("U"). If it is split at the next finer level,
      // the child set covers both its low and its new detail part.
      list[a][k++] = pa;
      if (l - 1 == ax.levels && pa < ax.lo[l - 2] - ax.lo[l - 1]) list[a][k++] = ax.lo[l - 1] + pa;
    } else if (ax.band[pa] == l) {
      const uint32_t q = pa - ax.lo[l];
      const uint32_t first = ax.lo[l - 1] + 2 * q;
      const uint32_t end = ax.lo[l - 2];  // end of the detail band of split l - 1
      const bool last = q + 1 == ax.lo[l - 1] - ax.lo[l];
      for (uint32_t c = first; c < end && c < first + (last ? 3u : 2u); ++c) list[a][k++] = c;
    } else {
      for (uint32_t c = 2 * pa; c < ax.lo[l - 1] && c < 2 * pa + 2; ++c) list[a][k++] = c;
    }
    count[a] = k;
  }
  int n = 0;
  for (int i0 = 0; i0 < count[0]; ++i0)
    for (int i1 = 0; i1 < count[1]; ++i1)
      for (int i2 = 0; i2 < count[2]; ++i2)
        for (int i3 = 0; i3 < count[3]; ++i3) {
          if (root && i0 == 0 && i1 == 0 && i2 == 0 && i3 == 0) continue;  // itself
          out[n++] = static_cast<uint32_t>(
              g_.shape.Index(list[0][i0], list[1][i1], list[2][i2], list[3][i3]));
        }
  return n;
}

bool SpihtTree::HasGrandchildren(uint32_t idx) const {
  // Every coefficient of level >= 2 has children, and a root (level L + 1) has its
  // children at level L; so grandchildren exist exactly from level 3 up: level
  // classes 1 (level >= 4) and 2 (level 3), and roots when L >= 2.
  const int cls = LevelClass(idx);
  return cls == 0 ? g_.levels >= 2 : cls <= 2;
}

void SpihtTree::BuildPositionTable() {
  const Shape4D& s = g_.shape;
  const uint32_t w = s.n[3];
  position_.resize(s.count());
  const int root = g_.levels + 1;
  // A row's entries depend only on the row's level over t, c, y and on whether it
  // is the first or last row: build each distinct row once and copy it.
  std::vector<std::vector<uint8_t>> rows(size_t(root + 1) * 4);
  auto row_for = [&](int l, uint8_t vertical) -> const std::vector<uint8_t>& {
    std::vector<uint8_t>& row = rows[size_t(l) * 4 + (vertical >> 5)];
    if (row.empty()) {
      row.resize(w);
      for (uint32_t x = 0; x < w; ++x) {
        const int bx = g_.axis[3].band[x];
        const int lx = bx != 0 && bx < l ? bx : l;
        const uint8_t cls = static_cast<uint8_t>(lx == root ? 0 : lx >= 4 ? 1 : 5 - lx);
        row[x] =
            static_cast<uint8_t>(cls | vertical | (x > 0 ? kLeft : 0) | (x + 1 < w ? kRight : 0));
      }
    }
    return row;
  };
  uint8_t* out = position_.data();
  for (uint32_t t = 0; t < s.n[0]; ++t) {
    for (uint32_t c = 0; c < s.n[1]; ++c) {
      for (uint32_t y = 0; y < s.n[2]; ++y, out += w) {
        // Level: the smallest non-zero band code over the axes (root: none).
        int l = root;
        for (int b : {int{g_.axis[0].band[t]}, int{g_.axis[1].band[c]}, int{g_.axis[2].band[y]}}) {
          if (b != 0 && b < l) l = b;
        }
        const uint8_t vertical =
            static_cast<uint8_t>((y > 0 ? kUp : 0) | (y + 1 < s.n[2] ? kDown : 0));
        const std::vector<uint8_t>& row = row_for(l, vertical);
        std::copy(row.begin(), row.end(), out);
      }
    }
  }
}

std::shared_ptr<const SpihtTree> SharedSpihtTree(const WaveletGeometry& geometry) {
  // Bounds: a few shapes (a stream has one or two), and no tree so large that
  // keeping it would hold memory a caller did not expect to stay in use.
  constexpr size_t kEntries = 4;
  constexpr size_t kMaxCoefficients = size_t{1} << 26;
  if (geometry.shape.count() > kMaxCoefficients) return std::make_shared<SpihtTree>(geometry);
  static std::mutex mutex;
  static std::vector<std::shared_ptr<const SpihtTree>> recent;  // most recent last
  // The most recent tree of this shape, moved to the end; null if none is kept.
  const auto find = [&]() -> std::shared_ptr<const SpihtTree> {
    for (size_t i = 0; i < recent.size(); ++i) {
      if (recent[i]->geometry().shape == geometry.shape) {
        std::shared_ptr<const SpihtTree> tree = recent[i];
        recent.erase(recent.begin() + static_cast<std::ptrdiff_t>(i));
        recent.push_back(tree);
        return tree;
      }
    }
    return nullptr;
  };
  {
    std::lock_guard<std::mutex> lock(mutex);
    if (auto tree = find()) return tree;
  }
  // Built outside the lock: threads decoding other shapes need not wait.
  auto tree = std::make_shared<const SpihtTree>(geometry);
  std::lock_guard<std::mutex> lock(mutex);
  if (auto other = find()) return other;  // another thread built it meanwhile
  if (recent.size() == kEntries) recent.erase(recent.begin());
  recent.push_back(tree);
  return tree;
}

}  // namespace fvv
