#include "codec/wavelet.h"

#include <algorithm>
#include <cstring>

#include "codec/simd.h"

namespace fvv {

const char* KernelName(WaveletKernel k) {
  switch (k) {
    case WaveletKernel::kHaar:
      return "haar";
    case WaveletKernel::kLeGall53:
      return "53";
    case WaveletKernel::kCdf97:
      return "97";
  }
  return "?";
}

WaveletGeometry::WaveletGeometry(const Shape4D& s) : shape(s) {
  for (int a = 0; a < kAxes; ++a) {
    AxisGeometry& g = axis[a];
    g.n = s.n[a];
    g.levels = 0;
    while ((1u << g.levels) < g.n && g.levels < kMaxLevelsPerAxis) ++g.levels;
    g.lo[0] = g.n;
    for (int k = 1; k <= kMaxLevelsPerAxis; ++k) g.lo[k] = (g.lo[k - 1] + 1) / 2;
    g.band.assign(g.n, 0);
    for (int k = 1; k <= g.levels; ++k)
      for (uint32_t p = g.lo[k]; p < g.lo[k - 1]; ++p) g.band[p] = static_cast<uint8_t>(k);
    levels = std::max(levels, g.levels);
  }
}

namespace {

// 9/7 lifting constants of ITU-T T.800 Table F.4, round(c * 2^16).
constexpr int32_t kAlpha = -103949, kBeta = -3472, kGamma = 57862, kDelta = 29066;
constexpr double kAlphaR = -1.586134342059924, kBetaR = -0.052980118572961,
                 kGammaR = 0.882911075530934, kDeltaR = 0.443506852043971;

// sum is the 32-bit (wrapped) sum of two neighbours, so the product is a 32x32 -> 64
// bit multiply, which vectorises (pmuldq) where a 64x64 one does not.
inline int32_t MulQ16(int32_t c, int32_t sum) {
  return static_cast<int32_t>((int64_t{c} * sum + 32768) >> 16);
}

// Lifting updates wrap modulo 2^32 instead of overflowing: valid streams never
// come near the limits, and a corrupt one must give defined (then clamped)
// output rather than undefined behaviour.
inline int32_t WrapAdd(int32_t a, int32_t b) {
  return static_cast<int32_t>(static_cast<uint32_t>(a) + static_cast<uint32_t>(b));
}
inline int32_t WrapSub(int32_t a, int32_t b) {
  return static_cast<int32_t>(static_cast<uint32_t>(a) - static_cast<uint32_t>(b));
}
inline int32_t NegMulQ16(int32_t c, int32_t sum) {
  return static_cast<int32_t>(-((int64_t{c} * sum + 32768) >> 16));
}

// Lifting step on row vectors: target row i gets f(src row i + src row i+di) where the
// neighbour index is clamped into [0, nsrc) (symmetric extension in deinterleaved form).
// Predict steps (target = odd rows d, source = even rows s) use neighbours i, i+1;
// update steps (target = s, source = d) use i-1, i.
template <typename F>
inline void PredictStep(int32_t* d, uint32_t nd, const int32_t* s, uint32_t ns, uint32_t v, F f) {
  for (uint32_t i = 0; i < nd; ++i) {
    const int32_t* a = s + size_t{i} * v;
    const int32_t* b = s + size_t{std::min(i + 1, ns - 1)} * v;
    int32_t* t = d + size_t{i} * v;
    for (uint32_t j = 0; j < v; ++j) t[j] = WrapAdd(t[j], f(a[j], b[j]));
  }
}
template <typename F>
inline void UpdateStep(int32_t* s, uint32_t ns, const int32_t* d, uint32_t nd, uint32_t v, F f) {
  for (uint32_t i = 0; i < ns; ++i) {
    const int32_t* a = d + size_t{i == 0 ? 0 : std::min(i - 1, nd - 1)} * v;
    const int32_t* b = d + size_t{std::min(i, nd - 1)} * v;
    int32_t* t = s + size_t{i} * v;
    for (uint32_t j = 0; j < v; ++j) t[j] = WrapAdd(t[j], f(a[j], b[j]));
  }
}

}  // namespace

// The lifting loops are the transform's inner loops: an AVX2 clone (chosen at load
// time where the CPU has it) runs them 8 lanes wide; results are identical.
FVV_SIMD_CLONES
void LiftForward(WaveletKernel kernel, uint32_t m, uint32_t v, int32_t* rows) {
  if (m < 2) return;
  const uint32_t ns = (m + 1) / 2, nd = m / 2;
  int32_t* s = rows;
  int32_t* d = rows + size_t{ns} * v;
  switch (kernel) {
    case WaveletKernel::kHaar:
      // d = odd - even; s = even + floor(d / 2). A trailing even sample stays as is.
      for (size_t i = 0; i < size_t{nd} * v; ++i) {
        d[i] = WrapSub(d[i], s[i]);
        s[i] = WrapAdd(s[i], d[i] >> 1);
      }
      break;
    case WaveletKernel::kLeGall53:
      PredictStep(d, nd, s, ns, v, [](int32_t a, int32_t b) {
        return static_cast<int32_t>(-((int64_t{a} + b) >> 1));
      });
      UpdateStep(s, ns, d, nd, v, [](int32_t a, int32_t b) {
        return static_cast<int32_t>((int64_t{a} + b + 2) >> 2);
      });
      break;
    case WaveletKernel::kCdf97:
      PredictStep(d, nd, s, ns, v,
                  [](int32_t a, int32_t b) { return MulQ16(kAlpha, WrapAdd(a, b)); });
      UpdateStep(s, ns, d, nd, v,
                 [](int32_t a, int32_t b) { return MulQ16(kBeta, WrapAdd(a, b)); });
      PredictStep(d, nd, s, ns, v,
                  [](int32_t a, int32_t b) { return MulQ16(kGamma, WrapAdd(a, b)); });
      UpdateStep(s, ns, d, nd, v,
                 [](int32_t a, int32_t b) { return MulQ16(kDelta, WrapAdd(a, b)); });
      break;
  }
}

FVV_SIMD_CLONES
void LiftInverse(WaveletKernel kernel, uint32_t m, uint32_t v, int32_t* rows) {
  if (m < 2) return;
  const uint32_t ns = (m + 1) / 2, nd = m / 2;
  int32_t* s = rows;
  int32_t* d = rows + size_t{ns} * v;
  switch (kernel) {
    case WaveletKernel::kHaar:
      for (size_t i = 0; i < size_t{nd} * v; ++i) {
        s[i] = WrapSub(s[i], d[i] >> 1);
        d[i] = WrapAdd(d[i], s[i]);
      }
      break;
    case WaveletKernel::kLeGall53:
      UpdateStep(s, ns, d, nd, v, [](int32_t a, int32_t b) {
        return static_cast<int32_t>(-((int64_t{a} + b + 2) >> 2));
      });
      PredictStep(d, nd, s, ns, v,
                  [](int32_t a, int32_t b) { return static_cast<int32_t>((int64_t{a} + b) >> 1); });
      break;
    case WaveletKernel::kCdf97:
      UpdateStep(s, ns, d, nd, v,
                 [](int32_t a, int32_t b) { return NegMulQ16(kDelta, WrapAdd(a, b)); });
      PredictStep(d, nd, s, ns, v,
                  [](int32_t a, int32_t b) { return NegMulQ16(kGamma, WrapAdd(a, b)); });
      UpdateStep(s, ns, d, nd, v,
                 [](int32_t a, int32_t b) { return NegMulQ16(kBeta, WrapAdd(a, b)); });
      PredictStep(d, nd, s, ns, v,
                  [](int32_t a, int32_t b) { return NegMulQ16(kAlpha, WrapAdd(a, b)); });
      break;
  }
}

void LiftInverseReal(WaveletKernel kernel, uint32_t m, double* x) {
  if (m < 2) return;
  const uint32_t ns = (m + 1) / 2, nd = m / 2;
  double* s = x;
  double* d = x + ns;
  auto sn = [&](uint32_t i) { return s[std::min(i, ns - 1)]; };
  auto dn = [&](int64_t i) { return d[std::clamp<int64_t>(i, 0, nd - 1)]; };
  auto update = [&](double c) {
    for (uint32_t i = 0; i < ns; ++i) s[i] -= c * (dn(int64_t{i} - 1) + dn(i));
  };
  auto predict = [&](double c) {
    for (uint32_t i = 0; i < nd; ++i) d[i] -= c * (sn(i) + sn(i + 1));
  };
  switch (kernel) {
    case WaveletKernel::kHaar:
      for (uint32_t i = 0; i < nd; ++i) {
        s[i] -= d[i] / 2;
        d[i] += s[i];
      }
      break;
    case WaveletKernel::kLeGall53:
      update(0.25);
      predict(-0.5);
      break;
    case WaveletKernel::kCdf97:
      update(kDeltaR);
      predict(kGammaR);
      update(kBetaR);
      predict(kAlphaR);
      break;
  }
  std::vector<double> tmp(x, x + m);
  for (uint32_t i = 0; i < m; ++i) x[i] = (i % 2 == 0) ? tmp[i / 2] : tmp[ns + i / 2];
}

namespace {

// Lines along the x axis are grouped this many at a time and transposed, so the
// lifting loops run over row vectors and vectorise like the other axes.
constexpr uint32_t kXGroup = 16;

struct Region {
  std::array<uint32_t, kAxes> ext;  // extents of R(l-1)
};

// One 1D pass along `axis` over the region; forward or inverse.
void AxisPass(WaveletKernel kernel, const Shape4D& shape, const Region& region, int axis,
              bool forward, const ParallelRunner& runner, int32_t* data) {
  const uint32_t m = region.ext[axis];
  if (m < 2) return;
  const uint32_t ns = (m + 1) / 2;
  const size_t stride = shape.Stride(axis);
  // Row position of sample i in the deinterleaved buffer.
  auto slot = [ns](uint32_t i) { return (i & 1) ? ns + i / 2 : i / 2; };

  if (axis == kAxes - 1) {
    // x axis: lines are rows; enumerate (t, c, y) rows in the region, in groups.
    const uint32_t rows = region.ext[0] * region.ext[1] * region.ext[2];
    const uint32_t groups = (rows + kXGroup - 1) / kXGroup;
    runner(groups, [&](uint32_t g) {
      std::vector<int32_t> buf(size_t{m} * kXGroup);
      const uint32_t r0 = g * kXGroup, nr = std::min(kXGroup, rows - r0);
      int32_t* line[kXGroup];
      for (uint32_t r = 0; r < nr; ++r) {
        uint32_t q = r0 + r;
        const uint32_t y = q % region.ext[2];
        q /= region.ext[2];
        const uint32_t c = q % region.ext[1], t = q / region.ext[1];
        line[r] = data + shape.Index(t, c, y, 0);
      }
      for (uint32_t i = 0; i < m; ++i) {
        int32_t* dst = buf.data() + size_t{forward ? slot(i) : i} * kXGroup;
        for (uint32_t r = 0; r < nr; ++r) dst[r] = line[r][i];
        for (uint32_t r = nr; r < kXGroup; ++r) dst[r] = 0;
      }
      if (forward)
        LiftForward(kernel, m, kXGroup, buf.data());
      else
        LiftInverse(kernel, m, kXGroup, buf.data());
      for (uint32_t i = 0; i < m; ++i) {
        const int32_t* src = buf.data() + size_t{forward ? i : slot(i)} * kXGroup;
        for (uint32_t r = 0; r < nr; ++r) line[r][i] = src[r];
      }
    });
    return;
  }

  // Other axes: a line of row vectors, each row vector being `vlen` contiguous
  // samples (the x extent of the region). Enumerate every combination of the axes
  // other than `axis` and x.
  const uint32_t vlen = region.ext[kAxes - 1];
  std::array<uint32_t, kAxes> loop = region.ext;
  loop[axis] = 1;
  loop[kAxes - 1] = 1;
  const uint32_t lines = loop[0] * loop[1] * loop[2];
  runner(lines, [&](uint32_t li) {
    std::array<uint32_t, kAxes> pos{0, 0, 0, 0};
    uint32_t q = li;
    for (int a = kAxes - 2; a >= 0; --a) {
      pos[a] = q % loop[a];
      q /= loop[a];
    }
    int32_t* base = data + shape.Index(pos[0], pos[1], pos[2], 0);
    std::vector<int32_t> buf(size_t{m} * vlen);
    for (uint32_t i = 0; i < m; ++i)
      std::memcpy(buf.data() + size_t{forward ? slot(i) : i} * vlen, base + i * stride,
                  vlen * sizeof(int32_t));
    if (forward)
      LiftForward(kernel, m, vlen, buf.data());
    else
      LiftInverse(kernel, m, vlen, buf.data());
    for (uint32_t i = 0; i < m; ++i)
      std::memcpy(base + i * stride, buf.data() + size_t{forward ? i : slot(i)} * vlen,
                  vlen * sizeof(int32_t));
  });
}

Region RegionAt(const WaveletGeometry& g, int l) {
  Region r;
  for (int a = 0; a < kAxes; ++a) r.ext[a] = g.RegionExtent(a, l);
  return r;
}

}  // namespace

void ForwardTransform4D(WaveletKernel kernel, const WaveletGeometry& g,
                        const ParallelRunner& runner, int32_t* data) {
  for (int l = 1; l <= g.levels; ++l) {
    const Region region = RegionAt(g, l - 1);
    for (int a = kAxes - 1; a >= 0; --a)
      if (g.AxisSplitAt(a, l)) AxisPass(kernel, g.shape, region, a, true, runner, data);
  }
}

void InverseTransform4D(WaveletKernel kernel, const WaveletGeometry& g,
                        const ParallelRunner& runner, int32_t* data) {
  for (int l = g.levels; l >= 1; --l) {
    const Region region = RegionAt(g, l - 1);
    for (int a = 0; a < kAxes; ++a)
      if (g.AxisSplitAt(a, l)) AxisPass(kernel, g.shape, region, a, false, runner, data);
  }
}

}  // namespace fvv
