#include "codec/fill.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "codec/subband_weights.h"

namespace fvv {
namespace {

Shape4D HalfShape(const Shape4D& s) {
  Shape4D h;
  for (int a = 0; a < kAxes; ++a) h.n[a] = (s.n[a] + 1) / 2;
  return h;
}

bool IsUnit(const Shape4D& s) { return s.count() == 1; }

// Bilinear pull along one axis: child i lies between its own parent i / 2
// (weight 12/16 of the "near" tap) and the parent on its other side ("far",
// 4/16), clamped at the ends. With kParent only near[i] = i / 2 is used.
struct PullTaps {
  std::vector<uint32_t> near, far;
  std::vector<uint8_t> near_weight;  // sixteenths
  PullTaps(uint32_t child_n, uint32_t parent_n)
      : near(child_n), far(child_n), near_weight(child_n, 12) {
    for (uint32_t i = 0; i < child_n; ++i) {
      near[i] = i / 2;
      const int64_t other = i % 2 == 0 ? int64_t{i / 2} - 1 : int64_t{i / 2} + 1;
      far[i] = static_cast<uint32_t>(std::clamp<int64_t>(other, 0, parent_n - 1));
    }
  }
};

// Rounded mean, half away from zero, in integers.
int32_t RoundedMean(int64_t sum, int64_t count) {
  return static_cast<int32_t>(sum >= 0 ? (sum + count / 2) / count : -((-sum + count / 2) / count));
}

}  // namespace

void FillUnused(const UsedMask& mask, int32_t fill_value, Plane4D* plane, FillPull pull) {
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
  // Walk back up: unused texels take their parent's final value, or the
  // bilinear interpolation of the four nearest parents in y and x.
  for (size_t k = levels.size() - 1; k-- > 0;) {
    Level& child = levels[k];
    const Level& parent = levels[k + 1];
    const auto& cs = child.shape.n;
    const std::array<PullTaps, 2> taps = {PullTaps(cs[2], parent.shape.n[2]),
                                          PullTaps(cs[3], parent.shape.n[3])};
    size_t i = 0;
    for (uint32_t t = 0; t < cs[0]; ++t)
      for (uint32_t c = 0; c < cs[1]; ++c)
        for (uint32_t y = 0; y < cs[2]; ++y) {
          const int32_t* p0 = &parent.value[parent.shape.Index(t / 2, c / 2, 0, 0)];
          const int32_t* near_row = p0 + size_t{taps[0].near[y]} * parent.shape.n[3];
          const int32_t* far_row = p0 + size_t{taps[0].far[y]} * parent.shape.n[3];
          for (uint32_t x = 0; x < cs[3]; ++x, ++i) {
            if (child.used[i]) continue;
            if (pull == FillPull::kParent) {
              child.value[i] = near_row[x / 2];
              continue;
            }
            const int64_t wy = taps[0].near_weight[y], wx = taps[1].near_weight[x];
            const uint32_t xn = taps[1].near[x], xf = taps[1].far[x];
            const int64_t sum = wy * (wx * near_row[xn] + (16 - wx) * near_row[xf]) +
                                (16 - wy) * (wx * far_row[xn] + (16 - wx) * far_row[xf]);
            child.value[i] = RoundedMean(sum, 256);
          }
        }
  }
  plane->samples = std::move(levels[0].value);
}

void SparseFill(WaveletKernel kernel, const UsedMask& mask, const SampleRange& range,
                const FillOptions& options, const ParallelRunner& runner, Plane4D* plane) {
  // Nothing to refine when every texel is used.
  if (options.iterations <= 0 || std::all_of(mask.begin(), mask.end(), [](uint8_t u) { return u; }))
    return;
  const WaveletGeometry g(plane->shape);
  const auto& n = g.shape.n;
  // The fill's own working precision (its output is whole samples).
  const int frac = DefaultFracBits(kernel);
  // Thresholds are in steps of the 8-bit scale; samples with range.frac
  // fractional bits have 2^range.frac of their units in one.
  const double scale = static_cast<double>(1 << frac) * static_cast<double>(1 << range.frac);
  // Per band: the reciprocal of its synthesis norm, the product over the four
  // axes of the norm each contributes at the band's level (the transform is
  // separable; subband_weights.h).
  std::vector<double> inv_norm(kBandIds, 0.0);
  for (int id = 0; id < kBandIds; ++id) {
    std::array<uint8_t, kAxes> codes;
    int rest = id;
    for (int a = kAxes - 1; a >= 0; --a, rest /= kBandCodes)
      codes[a] = static_cast<uint8_t>(rest % kBandCodes);
    double norm = 1;
    for (int a = 0; a < kAxes; ++a)
      norm *= AxisNormQ16(kernel, BandWeights::kOwnBand, g.axis[a], codes[a], BandLevel(codes)) /
              65536.0;
    inv_norm[id] = 1 / norm;
  }
  const uint32_t slices = n[0] * n[1];
  const size_t slice = size_t{n[2]} * n[3];
  const int32_t half = (1 << frac) >> 1;
  std::vector<int32_t> w(plane->samples.size());
  int32_t* samples = plane->samples.data();
  runner(slices, [&](uint32_t s) {
    for (size_t i = s * slice; i < (s + 1) * slice; ++i)
      w[i] = (samples[i] - range.offset) * (1 << frac);
  });
  const int iterations = options.iterations;
  for (int it = 0; it < iterations; ++it) {
    const double threshold =
        iterations == 1 ? options.end
                        : options.start * std::pow(options.end / options.start,
                                                   static_cast<double>(it) / (iterations - 1));
    ForwardTransform4D(kernel, g, runner, w.data());
    runner(slices, [&](uint32_t s) {
      // |c| * norm / 2^frac < threshold, as an integer bound per texel of a row.
      std::array<uint8_t, kAxes> codes{g.axis[0].band[s / n[1]], g.axis[1].band[s % n[1]], 0, 0};
      std::vector<int32_t> limit(n[3]);
      int32_t* row = w.data() + s * slice;
      for (uint32_t y = 0; y < n[2]; ++y, row += n[3]) {
        // A row's bounds depend on its band codes only, which change at band
        // edges: the rows of one band share them.
        if (y == 0 || g.axis[2].band[y] != codes[2]) {
          codes[2] = g.axis[2].band[y];
          for (uint32_t x = 0; x < n[3]; ++x) {
            codes[3] = g.axis[3].band[x];
            const double bound = threshold * scale * inv_norm[SubbandQuantisers::BandId(codes)];
            limit[x] = static_cast<int32_t>(std::min(std::ceil(bound), 2e9));
          }
        }
        for (uint32_t x = 0; x < n[3]; ++x) row[x] = std::abs(row[x]) < limit[x] ? 0 : row[x];
      }
    });
    InverseTransform4D(kernel, g, runner, w.data());
    // Used texels back, unused ones rounded and clamped; and the next
    // iteration's transform input in the same pass.
    runner(slices, [&](uint32_t s) {
      const uint8_t* used = mask.data();
      for (size_t i = s * slice; i < (s + 1) * slice; ++i) {
        const int32_t v = std::clamp(((w[i] + half) >> frac) + range.offset, range.min, range.max);
        samples[i] = used[i] ? samples[i] : v;
        w[i] = (samples[i] - range.offset) * (1 << frac);
      }
    });
  }
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
