#include "codec/wavelet.h"

#include <algorithm>
#include <cstring>
#include <functional>

#include "codec/base/simd.h"

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

// floor((C * x + 2^15) / 2^16) modulo 2^32, for x the 32-bit (wrapped) sum of two
// neighbours, in 32-bit operations only, so it vectorises without 64-bit lanes.
// With x = xh 2^16 + xl and C = ch 2^16 + cl (xl, cl in [0, 2^16)):
//   C x + 2^15 = (C xh + ch xl) 2^16 + (cl xl + 2^15),
// and cl xl + 2^15 < 2^32, so its floor quotient is an unsigned shift. The
// identity is exact, so this equals the 64-bit expression of SPEC.md 9.5.
template <int32_t C>
inline int32_t MulQ16(int32_t x) {
  constexpr int32_t ch = C >> 16;
  constexpr uint32_t cl = static_cast<uint32_t>(C) & 0xffffu;
  const int32_t xh = x >> 16;
  const uint32_t xl = static_cast<uint32_t>(x) & 0xffffu;
  return static_cast<int32_t>(static_cast<uint32_t>(C) * static_cast<uint32_t>(xh) +
                              static_cast<uint32_t>(ch) * xl + ((cl * xl + 32768u) >> 16));
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
template <int32_t C>
inline int32_t NegMulQ16(int32_t x) {
  return static_cast<int32_t>(0u - static_cast<uint32_t>(MulQ16<C>(x)));
}

// Lifting step on row vectors of v samples: target row i gets f(src row i + src
// row i+di) where the neighbour index is clamped into [0, nsrc) (symmetric
// extension in deinterleaved form). Predict steps (target = odd rows d, source =
// even rows s) use neighbours i, i+1; update steps (target = s, source = d) use
// i-1, i. The even and the odd rows each lie `pitch` samples apart, in one buffer
// or in two.
template <typename F>
FVV_ALWAYS_INLINE void PredictRow(int32_t* d, size_t d_pitch, const int32_t* s, size_t s_pitch,
                                  uint32_t ns, uint32_t v, uint32_t i, F f) {
  const int32_t* a = s + i * s_pitch;
  const int32_t* b = s + std::min(i + 1, ns - 1) * s_pitch;
  int32_t* t = d + i * d_pitch;
  for (uint32_t j = 0; j < v; ++j) t[j] = WrapAdd(t[j], f(a[j], b[j]));
}
template <typename F>
FVV_ALWAYS_INLINE void UpdateRow(int32_t* s, size_t s_pitch, const int32_t* d, size_t d_pitch,
                                 uint32_t nd, uint32_t v, uint32_t i, F f) {
  const int32_t* a = d + (i == 0 ? 0 : std::min(i - 1, nd - 1)) * d_pitch;
  const int32_t* b = d + std::min(i, nd - 1) * d_pitch;
  int32_t* t = s + i * s_pitch;
  for (uint32_t j = 0; j < v; ++j) t[j] = WrapAdd(t[j], f(a[j], b[j]));
}
template <typename F>
FVV_ALWAYS_INLINE void PredictStep(int32_t* d, size_t d_pitch, uint32_t nd, const int32_t* s,
                                   size_t s_pitch, uint32_t ns, uint32_t v, F f) {
  for (uint32_t i = 0; i < nd; ++i) PredictRow(d, d_pitch, s, s_pitch, ns, v, i, f);
}
template <typename F>
FVV_ALWAYS_INLINE void UpdateStep(int32_t* s, size_t s_pitch, uint32_t ns, const int32_t* d,
                                  size_t d_pitch, uint32_t nd, uint32_t v, F f) {
  for (uint32_t i = 0; i < ns; ++i) UpdateRow(s, s_pitch, d, d_pitch, nd, v, i, f);
}

// The same steps on one line (v = 1): the boundary samples are peeled off so the
// interior loops run over contiguous neighbours and vectorise along the line.
template <typename F>
FVV_ALWAYS_INLINE void PredictLine(int32_t* __restrict d, uint32_t nd, const int32_t* __restrict s,
                                   uint32_t ns, F f) {
  const uint32_t inner = std::min(nd, ns - 1);  // d[i] with both s[i] and s[i + 1]
  for (uint32_t i = 0; i < inner; ++i) d[i] = WrapAdd(d[i], f(s[i], s[i + 1]));
  for (uint32_t i = inner; i < nd; ++i) d[i] = WrapAdd(d[i], f(s[ns - 1], s[ns - 1]));
}
template <typename F>
FVV_ALWAYS_INLINE void UpdateLine(int32_t* __restrict s, uint32_t ns, const int32_t* __restrict d,
                                  uint32_t nd, F f) {
  s[0] = WrapAdd(s[0], f(d[0], d[0]));
  const uint32_t inner = std::min(ns, nd);  // s[i], i >= 1, with both d[i - 1] and d[i]
  for (uint32_t i = 1; i < inner; ++i) s[i] = WrapAdd(s[i], f(d[i - 1], d[i]));
  for (uint32_t i = std::max(inner, 1u); i < ns; ++i) s[i] = WrapAdd(s[i], f(d[nd - 1], d[nd - 1]));
}

// The kernels' lifting steps, applied through Predict/Update functors so that the
// row-vector and the single-line layouts share them.
template <typename Predict, typename Update>
FVV_ALWAYS_INLINE void ForwardSteps(WaveletKernel kernel, Predict predict, Update update) {
  switch (kernel) {
    case WaveletKernel::kHaar:
      break;  // callers handle Haar
    case WaveletKernel::kLeGall53:
      predict([](int32_t a, int32_t b) { return static_cast<int32_t>(-((int64_t{a} + b) >> 1)); });
      update([](int32_t a, int32_t b) { return static_cast<int32_t>((int64_t{a} + b + 2) >> 2); });
      break;
    case WaveletKernel::kCdf97:
      predict([](int32_t a, int32_t b) { return MulQ16<kAlpha>(WrapAdd(a, b)); });
      update([](int32_t a, int32_t b) { return MulQ16<kBeta>(WrapAdd(a, b)); });
      predict([](int32_t a, int32_t b) { return MulQ16<kGamma>(WrapAdd(a, b)); });
      update([](int32_t a, int32_t b) { return MulQ16<kDelta>(WrapAdd(a, b)); });
      break;
  }
}
// The inverse steps' functions, named so that the step-by-step form below and
// the sweep (InverseSweep) share them.
struct Inverse53Update {
  int32_t operator()(int32_t a, int32_t b) const {
    return static_cast<int32_t>(-((int64_t{a} + b + 2) >> 2));
  }
};
struct Inverse53Predict {
  int32_t operator()(int32_t a, int32_t b) const {
    return static_cast<int32_t>((int64_t{a} + b) >> 1);
  }
};
template <int32_t C>
struct InverseQ16Step {
  int32_t operator()(int32_t a, int32_t b) const { return NegMulQ16<C>(WrapAdd(a, b)); }
};

template <typename Predict, typename Update>
FVV_ALWAYS_INLINE void InverseSteps(WaveletKernel kernel, Predict predict, Update update) {
  switch (kernel) {
    case WaveletKernel::kHaar:
      break;
    case WaveletKernel::kLeGall53:
      update(Inverse53Update());
      predict(Inverse53Predict());
      break;
    case WaveletKernel::kCdf97:
      update(InverseQ16Step<kDelta>());
      predict(InverseQ16Step<kGamma>());
      update(InverseQ16Step<kBeta>());
      predict(InverseQ16Step<kAlpha>());
      break;
  }
}

// The inverse steps on row vectors as one sweep down the rows instead of one
// sweep per step, so each row comes from memory once rather than four times.
// While the sweep is at k, each step works on the row its inputs are ready for:
// an update of s[j] reads d[j - 1] and d[j] as the step before left them, a
// predict of d[j] reads s[j] and s[j + 1], so a predict after an update trails
// it by one row, an update after a predict runs on the same row. No row is
// changed before every read of its previous value is done (the readers of a
// row run on the same or the earlier sweep position), so every sample gets the
// same operations on the same values as step by step: the result is identical.
template <typename UpdateRow, typename PredictRow>
FVV_ALWAYS_INLINE void InverseSweep(WaveletKernel kernel, uint32_t ns, uint32_t nd,
                                    UpdateRow update, PredictRow predict) {
  if (kernel == WaveletKernel::kLeGall53) {
    for (uint32_t k = 0; k <= ns; ++k) {
      if (k < ns) update(k, Inverse53Update());
      if (k >= 1 && k - 1 < nd) predict(k - 1, Inverse53Predict());
    }
    return;
  }
  for (uint32_t k = 0; k <= ns + 1; ++k) {
    if (k < ns) update(k, InverseQ16Step<kDelta>());
    if (k >= 1 && k - 1 < nd) predict(k - 1, InverseQ16Step<kGamma>());
    if (k >= 1 && k - 1 < ns) update(k - 1, InverseQ16Step<kBeta>());
    if (k >= 2 && k - 2 < nd) predict(k - 2, InverseQ16Step<kAlpha>());
  }
}

// Both directions, written once, inlined into each entry point: m rows of v
// samples, deinterleaved into the ceil(m / 2) even rows `s` and the floor(m / 2)
// odd rows `d`, each row `pitch` samples after the one before (one line: v and
// the pitches 1).
template <bool kForward>
FVV_ALWAYS_INLINE void Lift(WaveletKernel kernel, uint32_t m, uint32_t v, int32_t* s,
                            size_t s_pitch, int32_t* d, size_t d_pitch) {
  if (m < 2) return;
  const uint32_t ns = (m + 1) / 2, nd = m / 2;
  if (kernel == WaveletKernel::kHaar) {
    // Forward: d = odd - even; s = even + floor(d / 2). A trailing even sample
    // stays as is. The inverse undoes the two steps in reverse order.
    for (uint32_t i = 0; i < nd; ++i) {
      int32_t* si = s + i * s_pitch;
      int32_t* di = d + i * d_pitch;
      for (uint32_t j = 0; j < v; ++j) {
        if (kForward) {
          di[j] = WrapSub(di[j], si[j]);
          si[j] = WrapAdd(si[j], di[j] >> 1);
        } else {
          si[j] = WrapSub(si[j], di[j] >> 1);
          di[j] = WrapAdd(di[j], si[j]);
        }
      }
    }
    return;
  }
  const auto steps = [kernel](auto predict, auto update) FVV_INLINE_LAMBDA {
    if (kForward) {
      ForwardSteps(kernel, predict, update);
    } else {
      InverseSteps(kernel, predict, update);
    }
  };
  if (v == 1 && s_pitch == 1 && d_pitch == 1) {
    steps([&](auto f) FVV_INLINE_LAMBDA { PredictLine(d, nd, s, ns, f); },
          [&](auto f) FVV_INLINE_LAMBDA { UpdateLine(s, ns, d, nd, f); });
  } else if (!kForward) {
    InverseSweep(
        kernel, ns, nd,
        [&](uint32_t i, auto f)
            FVV_INLINE_LAMBDA { UpdateRow(s, s_pitch, d, d_pitch, nd, v, i, f); },
        [&](uint32_t i, auto f)
            FVV_INLINE_LAMBDA { PredictRow(d, d_pitch, s, s_pitch, ns, v, i, f); });
  } else {
    steps([&](auto f) FVV_INLINE_LAMBDA { PredictStep(d, d_pitch, nd, s, s_pitch, ns, v, f); },
          [&](auto f) FVV_INLINE_LAMBDA { UpdateStep(s, s_pitch, ns, d, d_pitch, nd, v, f); });
  }
}

// The inverse on rows whose even and odd halves lie apart (the y pass keeps its
// low rows in the plane and its high rows in scratch; see PlaneInversePasses).
FVV_SIMD_CLONES
void LiftInverseSplit(WaveletKernel kernel, uint32_t m, uint32_t v, int32_t* s, size_t s_pitch,
                      int32_t* d, size_t d_pitch) {
  Lift<false>(kernel, m, v, s, s_pitch, d, d_pitch);
}

}  // namespace

// The lifting loops are the transform's inner loops: an AVX2 clone (chosen at load
// time where the CPU has it) runs them 8 lanes wide; results are identical.
FVV_SIMD_CLONES
void LiftForward(WaveletKernel kernel, uint32_t m, uint32_t v, int32_t* rows) {
  Lift<true>(kernel, m, v, rows, v, rows + size_t{(m + 1) / 2} * v, v);
}

FVV_SIMD_CLONES
void LiftInverse(WaveletKernel kernel, uint32_t m, uint32_t v, int32_t* rows) {
  Lift<false>(kernel, m, v, rows, v, rows + size_t{(m + 1) / 2} * v, v);
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

// Rows along the x axis are handed out this many to a task.
constexpr uint32_t kRowsPerTask = 16;
// Lines along the other axes are cut into column strips of at most this many
// samples (m rows x strip), so a strip's lifting steps run in the core's cache.
constexpr size_t kStripSamples = 128 * 1024;
// With at least this many (t, c) planes in a level's region, each plane's y and
// x passes run together as one task while the plane is in cache; with fewer,
// each pass is spread over the runner on its own.
constexpr uint32_t kMinPlanesToFuse = 4;

struct Region {
  std::array<uint32_t, kAxes> ext;  // extents of R(l-1)
  uint32_t Planes() const { return ext[0] * ext[1]; }
};

// Scratch kept per thread across passes and blocks: kLine for one line or
// strip, kHighRows for a plane's high-pass rows (PlaneInversePasses).
enum ScratchUse { kLine = 0, kHighRows = 1 };
int32_t* Scratch(ScratchUse use, size_t samples) {
  thread_local std::vector<int32_t> buffers[2];
  std::vector<int32_t>& buffer = buffers[use];
  if (buffer.size() < samples) buffer.resize(samples);
  return buffer.data();
}

// One row's inverse x pass: `src` lifted and interleaved into `dst`. A `src`
// that is not `dst` is lifted where it is (the caller has no further use for
// it); one that is, in scratch.
void RowInverse(WaveletKernel kernel, uint32_t m, int32_t* src, int32_t* dst) {
  const uint32_t ns = (m + 1) / 2, nd = m / 2;
  int32_t* buf = src;
  if (src == dst) {
    buf = Scratch(kLine, m);
    std::memcpy(buf, src, m * sizeof(int32_t));
  }
  LiftInverse(kernel, m, 1, buf);
  for (uint32_t i = 0; i < nd; ++i) {
    dst[2 * i] = buf[i];
    dst[2 * i + 1] = buf[ns + i];
  }
  if (ns > nd) dst[m - 1] = buf[nd];
}

// Rows along x, each lifted on its own in the cache-resident scratch and then
// (inverse) interleaved back or (forward) stored deinterleaved.
FVV_SIMD_CLONES
void RowsPass(WaveletKernel kernel, uint32_t m, bool forward, int32_t* row, size_t row_stride,
              uint32_t rows) {
  const uint32_t ns = (m + 1) / 2, nd = m / 2;
  int32_t* buf = Scratch(kLine, m);
  for (uint32_t r = 0; r < rows; ++r, row += row_stride) {
    if (forward) {
      for (uint32_t i = 0; i < nd; ++i) {
        buf[i] = row[2 * i];
        buf[ns + i] = row[2 * i + 1];
      }
      if (ns > nd) buf[nd] = row[m - 1];
      LiftForward(kernel, m, 1, buf);
      std::memcpy(row, buf, m * sizeof(int32_t));
    } else {
      RowInverse(kernel, m, row, row);
    }
  }
}

// Inverse lifting of m rows of `width` samples, `stride` apart, deinterleaved
// (low rows first), without gathering them: the high rows are copied to
// scratch and the low rows lifted where they are. Then `emit(src, i)` is called
// for every output row i, from the bottom up, with the lifted row it is made of
// (low row i / 2 for even i, high row i / 2 for odd i), which nothing reads
// afterwards: the caller writes output row i from it, and may use it as scratch
// meanwhile. Bottom up, no low row is overwritten before it is read, as low row
// i / 2 sits at row i / 2 <= i.
template <typename Emit>
void InverseRowsInPlace(WaveletKernel kernel, uint32_t m, uint32_t width, int32_t* base,
                        size_t stride, Emit emit) {
  const uint32_t ns = (m + 1) / 2, nd = m / 2;
  int32_t* high = Scratch(kHighRows, size_t{nd} * width);
  for (uint32_t i = 0; i < nd; ++i)
    std::memcpy(high + size_t{i} * width, base + (ns + i) * stride, width * sizeof(int32_t));
  LiftInverseSplit(kernel, m, width, base, stride, high, width);
  for (uint32_t i = m; i-- > 0;)
    emit((i & 1) ? high + size_t{i / 2} * width : base + (i / 2) * stride, i);
}

// One strip of a line along a slower axis: m row vectors of `width` samples,
// `stride` apart. Forward: gathered deinterleaved into scratch, lifted and
// stored back. Inverse: lifted in place and interleaved back.
void StripPass(WaveletKernel kernel, uint32_t m, bool forward, int32_t* base, size_t stride,
               uint32_t width) {
  if (!forward) {
    InverseRowsInPlace(kernel, m, width, base, stride, [&](int32_t* src, uint32_t i) {
      int32_t* dst = base + i * stride;
      if (src != dst) std::memcpy(dst, src, width * sizeof(int32_t));
    });
    return;
  }
  const uint32_t ns = (m + 1) / 2;
  int32_t* buf = Scratch(kLine, size_t{m} * width);
  for (uint32_t i = 0; i < m; ++i) {
    const uint32_t slot = (i & 1) ? ns + i / 2 : i / 2;  // deinterleaved position
    std::memcpy(buf + size_t{slot} * width, base + i * stride, width * sizeof(int32_t));
  }
  LiftForward(kernel, m, width, buf);
  for (uint32_t i = 0; i < m; ++i)
    std::memcpy(base + i * stride, buf + size_t{i} * width, width * sizeof(int32_t));
}

uint32_t StripWidth(uint32_t m, uint32_t vlen) {
  return static_cast<uint32_t>(
      std::min<size_t>(vlen, std::max<size_t>(16, kStripSamples / m / 16 * 16)));
}

// The inverse y and x passes of one (t, c) plane of the region (whichever the
// level splits): the x pass interleaves the y pass's rows as it reads them for
// its own lifting, so neither pass copies the plane in and out of scratch.
void PlaneInversePasses(WaveletKernel kernel, const Shape4D& shape, const Region& region,
                        bool split_y, bool split_x, int32_t* plane) {
  const uint32_t m = region.ext[2], width = region.ext[3];
  const size_t stride = shape.Stride(2);
  if (!split_y || m < 2) {
    if (split_x) RowsPass(kernel, width, false, plane, stride, m);
    return;
  }
  InverseRowsInPlace(kernel, m, width, plane, stride, [&](int32_t* src, uint32_t i) {
    int32_t* dst = plane + i * stride;
    if (split_x) {
      RowInverse(kernel, width, src, dst);
    } else if (src != dst) {
      std::memcpy(dst, src, width * sizeof(int32_t));
    }
  });
}

// The forward y pass of one (t, c) plane of the region, whose row 0 starts at `plane`.
void PlaneForwardYPass(WaveletKernel kernel, const Shape4D& shape, const Region& region,
                       int32_t* plane) {
  const uint32_t m = region.ext[2], vlen = region.ext[3];
  if (m < 2) return;
  const uint32_t strip = StripWidth(m, vlen);
  for (uint32_t x0 = 0; x0 < vlen; x0 += strip)
    StripPass(kernel, m, true, plane + x0, shape.Stride(2), std::min(strip, vlen - x0));
}

// One 1D pass along `axis` over the region, spread over the runner.
void AxisPass(WaveletKernel kernel, const Shape4D& shape, const Region& region, int axis,
              bool forward, const ParallelRunner& runner, int32_t* data) {
  const uint32_t m = region.ext[axis];
  if (m < 2) return;
  if (axis == kAxes - 1) {
    // x axis: lines are rows; enumerate (t, c, y) rows in the region, in groups.
    const uint32_t rows = region.ext[0] * region.ext[1] * region.ext[2];
    runner((rows + kRowsPerTask - 1) / kRowsPerTask, [&](uint32_t task) {
      const uint32_t r0 = task * kRowsPerTask, r1 = std::min(rows, r0 + kRowsPerTask);
      for (uint32_t q = r0; q < r1;) {
        // A run of rows of one plane is evenly strided.
        const uint32_t y = q % region.ext[2], tc = q / region.ext[2];
        const uint32_t run = std::min(r1 - q, region.ext[2] - y);
        const uint32_t c = tc % region.ext[1], t = tc / region.ext[1];
        RowsPass(kernel, m, forward, data + shape.Index(t, c, y, 0), shape.Stride(2), run);
        q += run;
      }
    });
    return;
  }
  // Other axes: a line of row vectors, each row vector being `vlen` contiguous
  // samples (the x extent of the region), cut into strips. Enumerate every
  // combination of the axes other than `axis` and x, times the strips.
  const uint32_t vlen = region.ext[kAxes - 1];
  const uint32_t strip = StripWidth(m, vlen);
  const uint32_t strips = (vlen + strip - 1) / strip;
  std::array<uint32_t, kAxes> loop = region.ext;
  loop[axis] = 1;
  loop[kAxes - 1] = 1;
  const uint32_t lines = loop[0] * loop[1] * loop[2];
  runner(lines * strips, [&](uint32_t task) {
    const uint32_t x0 = task % strips * strip;
    std::array<uint32_t, kAxes> pos{0, 0, 0, 0};
    uint32_t q = task / strips;
    for (int a = kAxes - 2; a >= 0; --a) {
      pos[a] = q % loop[a];
      q /= loop[a];
    }
    StripPass(kernel, m, forward, data + shape.Index(pos[0], pos[1], pos[2], x0),
              shape.Stride(axis), std::min(strip, vlen - x0));
  });
}

// The spatial passes of one level: per plane when there are enough planes
// (inverse: y then x; forward: x then y, the order of the level's passes),
// otherwise axis by axis. `plane_done(begin, end)` is called on each plane's
// sample range once its passes are over (fused case only; returns whether it
// was used).
bool SpatialPasses(WaveletKernel kernel, const WaveletGeometry& g, const Region& region, int l,
                   bool forward, const ParallelRunner& runner, int32_t* data,
                   const std::function<void(size_t, size_t)>* plane_done) {
  const bool split_y = g.AxisSplitAt(2, l), split_x = g.AxisSplitAt(3, l);
  const Shape4D& shape = g.shape;
  if (region.Planes() < kMinPlanesToFuse) {
    if (forward && split_x) AxisPass(kernel, shape, region, 3, true, runner, data);
    if (split_y) AxisPass(kernel, shape, region, 2, forward, runner, data);
    if (!forward && split_x) AxisPass(kernel, shape, region, 3, false, runner, data);
    return false;
  }
  runner(region.Planes(), [&](uint32_t p) {
    int32_t* plane = data + shape.Index(p / region.ext[1], p % region.ext[1], 0, 0);
    const uint32_t rows = region.ext[2];
    if (forward) {
      if (split_x) RowsPass(kernel, region.ext[3], true, plane, shape.Stride(2), rows);
      if (split_y) PlaneForwardYPass(kernel, shape, region, plane);
    } else {
      PlaneInversePasses(kernel, shape, region, split_y, split_x, plane);
    }
    if (plane_done) {
      const size_t begin = static_cast<size_t>(plane - data);
      (*plane_done)(begin, begin + shape.Stride(1));
    }
  });
  return true;
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
    SpatialPasses(kernel, g, region, l, true, runner, data, nullptr);
    for (int a = 1; a >= 0; --a)
      if (g.AxisSplitAt(a, l)) AxisPass(kernel, g.shape, region, a, true, runner, data);
  }
}

void InverseTransform4D(WaveletKernel kernel, const WaveletGeometry& g,
                        const ParallelRunner& runner, int32_t* data,
                        const std::function<void(size_t, size_t)>& finish) {
  constexpr size_t kSlice = 1 << 16;  // finishing in slices over the runner otherwise
  bool finished = false;
  for (int l = g.levels; l >= 1; --l) {
    const Region region = RegionAt(g, l - 1);
    for (int a = 0; a < 2; ++a)
      if (g.AxisSplitAt(a, l)) AxisPass(kernel, g.shape, region, a, false, runner, data);
    // Level 1's region is the whole block, so its planes are final after it.
    const bool last = l == 1 && finish;
    finished =
        SpatialPasses(kernel, g, region, l, false, runner, data, last ? &finish : nullptr) && last;
  }
  if (finish && !finished) {
    const size_t count = g.shape.count();
    runner(static_cast<uint32_t>((count + kSlice - 1) / kSlice), [&](uint32_t k) {
      finish(size_t{k} * kSlice, std::min(count, (size_t{k} + 1) * kSlice));
    });
  }
}

}  // namespace fvv
