#include "codec/quadtree4d_common.h"

#include <algorithm>

namespace fvv {
QuadtreeLayout::QuadtreeLayout(const WaveletGeometry& g) : shape_(g.shape) {
  const int levels = g.levels;
  auto add = [&](int level, uint8_t axes) {
    QuadtreeBand b;
    b.level = level;
    b.axes = axes;
    b.cls = static_cast<uint8_t>(level > levels ? 3 : level >= 3 ? 2 : level - 1);
    for (int a = 0; a < kAxes; ++a) {
      if (axes >> a & 1) {
        b.lo[a] = g.axis[a].lo[level];
        b.n[a] = g.axis[a].lo[level - 1] - g.axis[a].lo[level];
      } else {
        b.lo[a] = 0;
        b.n[a] = g.RegionExtent(a, std::min(level, levels));
      }
    }
    bands_.push_back(b);
  };
  add(levels + 1, 0);
  for (int l = levels; l >= 1; --l) {
    uint8_t split = 0;
    for (int a = 0; a < kAxes; ++a)
      if (g.AxisSplitAt(a, l)) split = static_cast<uint8_t>(split | 1 << a);
    for (uint8_t m = 1; m < 16; ++m) {
      if ((m & split) != m) continue;
      add(l, m);
      QuadtreeBand& b = bands_.back();
      // The parent: level l + 1, the same high-pass axes (listed before this band).
      for (size_t i = 0; i + 1 < bands_.size(); ++i) {
        const QuadtreeBand& p = bands_[i];
        if (p.level == l + 1 && p.axes == m) {
          b.parent = static_cast<int>(i);
          for (int a = 0; a < kAxes; ++a) b.parent_halved[a] = p.n[a] < b.n[a];
        }
      }
    }
  }
  for (QuadtreeBand& b : bands_) {
    std::array<uint32_t, kAxes> d = b.n;
    for (;;) {
      b.dims.push_back(d);
      b.offset.push_back(static_cast<uint32_t>(nodes_));
      nodes_ += size_t{d[0]} * d[1] * d[2] * d[3];
      if (d[0] == 1 && d[1] == 1 && d[2] == 1 && d[3] == 1) break;
      for (int a = 0; a < kAxes; ++a) d[a] = (d[a] + 1) / 2;
    }
    b.top = static_cast<int>(b.dims.size()) - 1;
    top_ = std::max(top_, b.top);
  }
}

}  // namespace fvv
