#include "codec/fill.h"

#include <cstdlib>

namespace fvv {
namespace {

Shape4D HalfShape(const Shape4D& s) {
  Shape4D h;
  for (int a = 0; a < kAxes; ++a) h.n[a] = (s.n[a] + 1) / 2;
  return h;
}

bool IsUnit(const Shape4D& s) { return s.count() == 1; }

// Rounded mean, half away from zero, in integers.
int32_t RoundedMean(int64_t sum, int64_t count) {
  return static_cast<int32_t>(sum >= 0 ? (sum + count / 2) / count : -((-sum + count / 2) / count));
}

}  // namespace

void FillUnused(const UsedMask& mask, int32_t fill_value, Plane4D* plane) {
  struct Level {
    Shape4D shape;
    std::vector<int32_t> value;
    std::vector<uint8_t> used;
  };
  std::vector<Level> levels;
  levels.push_back({plane->shape, plane->samples, mask});
  while (!IsUnit(levels.back().shape)) {
    const Level& child = levels.back();
    Level parent;
    parent.shape = HalfShape(child.shape);
    const size_t pn = parent.shape.count();
    std::vector<int64_t> sum(pn, 0);
    std::vector<int32_t> count(pn, 0);
    const auto& cs = child.shape.n;
    size_t i = 0;
    for (uint32_t t = 0; t < cs[0]; ++t)
      for (uint32_t c = 0; c < cs[1]; ++c)
        for (uint32_t y = 0; y < cs[2]; ++y)
          for (uint32_t x = 0; x < cs[3]; ++x, ++i) {
            if (!child.used[i]) continue;
            const size_t p = parent.shape.Index(t / 2, c / 2, y / 2, x / 2);
            sum[p] += child.value[i];
            ++count[p];
          }
    parent.value.resize(pn);
    parent.used.resize(pn);
    for (size_t p = 0; p < pn; ++p) {
      parent.used[p] = count[p] > 0;
      parent.value[p] = count[p] > 0 ? RoundedMean(sum[p], count[p]) : 0;
    }
    levels.push_back(std::move(parent));
  }
  if (!levels.back().used[0]) levels.back().value[0] = fill_value;
  // Walk back up: unused texels inherit the parent's final value.
  for (size_t k = levels.size() - 1; k-- > 0;) {
    Level& child = levels[k];
    const Level& parent = levels[k + 1];
    const auto& cs = child.shape.n;
    size_t i = 0;
    for (uint32_t t = 0; t < cs[0]; ++t)
      for (uint32_t c = 0; c < cs[1]; ++c)
        for (uint32_t y = 0; y < cs[2]; ++y)
          for (uint32_t x = 0; x < cs[3]; ++x, ++i) {
            if (child.used[i]) continue;
            child.value[i] = parent.value[parent.shape.Index(t / 2, c / 2, y / 2, x / 2)];
          }
  }
  plane->samples = std::move(levels[0].value);
}

UsedMask DownsampleMask(const UsedMask& mask, const Shape4D& luma, const Shape4D& chroma) {
  UsedMask out(chroma.count(), 0);
  size_t i = 0;
  for (uint32_t t = 0; t < luma.n[0]; ++t)
    for (uint32_t c = 0; c < luma.n[1]; ++c)
      for (uint32_t y = 0; y < luma.n[2]; ++y)
        for (uint32_t x = 0; x < luma.n[3]; ++x, ++i)
          if (mask[i])
            out[chroma.Index(t, c, y * chroma.n[2] / luma.n[2], x * chroma.n[3] / luma.n[3])] = 1;
  return out;
}

}  // namespace fvv
