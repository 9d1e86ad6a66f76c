#include <algorithm>
#include <cmath>

#include "codec/bisk.h"
#include "codec/colour.h"
#include "codec/predictive_texture.h"
#include "codec/predictive_texture_support.h"
#include "codec/sa_wavelet.h"

namespace fvv {
namespace {

// A stream and where its planes end.
struct CodedSignal {
  std::vector<uint8_t> stream;
  std::vector<size_t> plane_ends;  // from the top plane down
};

CodedSignal Code(const std::vector<int32_t>& signal, const std::vector<uint8_t>& shape,
                 uint32_t width, uint32_t height, WaveletKernel kernel, int levels) {
  ShapePlane p;
  p.width = width, p.height = height, p.samples = signal, p.mask = shape;
  CodedSignal c;
  c.stream = BiskEncode(p, kernel, levels, &c.plane_ends);
  return c;
}

// The prefix of a stream at bitplane threshold `tau`: planes above floor(tau)
// whole, plane floor(tau) in proportion to tau's fraction left.
std::vector<uint8_t> Cut(const CodedSignal& c, double tau) {
  if (c.stream.size() <= 1 || c.stream[0] == 255 || tau <= 0) return c.stream;
  const int top = c.stream[0];
  // E(p): bytes to complete plane p (p = top .. 0); E(top + 1) = the header.
  const auto end = [&](int p) -> double {
    if (p > top) return 1.0;
    const size_t k = size_t(top - p);
    return double(k < c.plane_ends.size() ? c.plane_ends[k] : c.stream.size());
  };
  const int i = int(std::floor(tau));
  const double frac = tau - i;
  const double bytes = end(i) - frac * (end(i) - end(i + 1));
  const size_t keep = std::clamp<size_t>(size_t(std::llround(bytes)), 1, c.stream.size());
  return std::vector<uint8_t>(c.stream.begin(), c.stream.begin() + keep);
}

// The GOP in YUV (BT.601), per (t, c) and channel.
std::vector<std::array<std::vector<int32_t>, 3>> ToYuv(const PredictiveGop& gop) {
  const size_t texels = size_t(gop.width) * gop.height;
  std::vector<std::array<std::vector<int32_t>, 3>> out(size_t(gop.frames) * gop.cameras);
  for (size_t tc = 0; tc < out.size(); ++tc) {
    for (auto& ch : out[tc]) ch.assign(texels, 0);
    for (size_t i = 0; i < texels; ++i) {
      if (!gop.mask[tc * texels + i]) continue;
      const uint8_t* p = &gop.rgb[(tc * texels + i) * 3];
      const Yuv yuv = RgbToYuv(ColourSpace::kYCbCr601, p[0], p[1], p[2]);
      out[tc][0][i] = yuv.y, out[tc][1][i] = yuv.u, out[tc][2][i] = yuv.v;
    }
  }
  return out;
}

int32_t RoundedMean(int64_t sum, int64_t count) {
  return int32_t(sum >= 0 ? (sum + count / 2) / count : -((-sum + count / 2) / count));
}

// One closed-loop pass at threshold `tau`: the streams, and in `rec` what a
// decoder reconstructs from them.
PredictiveStreams EncodeAt(const PredictiveGop& gop,
                           const std::vector<std::array<std::vector<int32_t>, 3>>& yuv,
                           const PredictiveSupports& sup, WaveletKernel kernel, int levels,
                           double tau, PredictiveDecoded* rec) {
  const size_t texels = size_t(gop.width) * gop.height;
  const size_t views = size_t(gop.frames) * gop.cameras;
  PredictiveStreams s;
  s.kernel = kernel;
  s.levels = levels;
  s.r0.assign(gop.frames, {});
  s.r.assign(views, {});
  rec->r0.assign(gop.frames, {});
  rec->r.assign(views, {});
  rec->yuv.assign(views, {});
  Status ignored = Status::Ok();
  const auto code = [&](const std::vector<int32_t>& signal, const std::vector<uint8_t>& shape,
                        std::vector<uint8_t>* stream) {
    *stream = Cut(Code(signal, shape, gop.width, gop.height, kernel, levels), tau);
    // The reference is what the decoder will have: the cut stream decoded.
    return DecodeSignal(*stream, kernel, levels, gop.width, gop.height, shape, &ignored);
  };
  for (int k = 0; k < 3; ++k) {
    // T0(t) and T00: means over the cameras that saw each texel.
    std::vector<std::vector<int32_t>> t0(gop.frames, std::vector<int32_t>(texels, 0));
    std::vector<int64_t> all_sum(texels, 0), all_count(texels, 0);
    for (uint32_t t = 0; t < gop.frames; ++t) {
      std::vector<int64_t> sum(texels, 0), count(texels, 0);
      for (uint32_t c = 0; c < gop.cameras; ++c) {
        const size_t tc = size_t(t) * gop.cameras + c;
        for (size_t i = 0; i < texels; ++i) {
          if (gop.mask[tc * texels + i]) sum[i] += yuv[tc][k][i], ++count[i];
        }
      }
      for (size_t i = 0; i < texels; ++i) {
        if (count[i]) t0[t][i] = RoundedMean(sum[i], count[i]);
        all_sum[i] += sum[i];
        all_count[i] += count[i];
      }
    }
    std::vector<int32_t> t00(texels, 0);
    for (size_t i = 0; i < texels; ++i) {
      if (all_count[i]) t00[i] = RoundedMean(all_sum[i], all_count[i]) - kPredictiveLevelShift;
    }
    rec->t00[k] = code(t00, sup.all, &s.t00[k]);
    for (size_t i = 0; i < texels; ++i) {
      if (sup.all[i]) rec->t00[k][i] += kPredictiveLevelShift;
    }
    for (uint32_t t = 0; t < gop.frames; ++t) {
      std::vector<int32_t> r0(texels, 0);
      for (size_t i = 0; i < texels; ++i) {
        if (sup.frame[t][i]) r0[i] = t0[t][i] - rec->t00[k][i];
      }
      rec->r0[t][k] = code(r0, sup.frame[t], &s.r0[t][k]);
      for (uint32_t c = 0; c < gop.cameras; ++c) {
        const size_t tc = size_t(t) * gop.cameras + c;
        const std::vector<uint8_t> shape(gop.mask.begin() + tc * texels,
                                         gop.mask.begin() + (tc + 1) * texels);
        std::vector<int32_t> r(texels, 0);
        for (size_t i = 0; i < texels; ++i) {
          if (shape[i]) r[i] = yuv[tc][k][i] - (rec->t00[k][i] + rec->r0[t][k][i]);
        }
        rec->r[tc][k] = code(r, shape, &s.r[tc][k]);
        std::vector<int32_t>& out = rec->yuv[tc][k];
        out.assign(texels, 0);
        for (size_t i = 0; i < texels; ++i) {
          if (shape[i]) out[i] = rec->t00[k][i] + rec->r0[t][k][i] + rec->r[tc][k][i];
        }
      }
    }
  }
  return s;
}

}  // namespace

StatusOr<PredictiveStreams> EncodePredictive(const PredictiveGop& gop,
                                             const PredictiveEncodeOptions& o,
                                             PredictiveDecoded* reconstruction) {
  const size_t texels = size_t(gop.width) * gop.height;
  const size_t views = size_t(gop.frames) * gop.cameras;
  if (gop.frames == 0 || gop.cameras == 0 || gop.width == 0 || gop.height == 0 ||
      gop.rgb.size() != views * texels * 3 || gop.mask.size() != views * texels) {
    return InvalidArgument("predictive texture: the GOP's arrays do not match its shape");
  }
  const PredictiveSupports sup = MakeSupports(gop);
  const std::vector<std::array<std::vector<int32_t>, 3>> yuv = ToYuv(gop);
  const int levels = ShapeAdaptiveLevels(gop.width, gop.height);
  PredictiveDecoded rec;
  PredictiveStreams best = EncodeAt(gop, yuv, sup, o.kernel, levels, 0.0, &rec);
  if (o.target_bytes > 0 && best.Bytes() > o.target_bytes) {
    // The smallest threshold (best quality) whose streams fit: bytes fall as
    // tau grows. Bisection over whole closed-loop passes.
    double lo = 0, hi = 24;
    PredictiveDecoded hi_rec;
    PredictiveStreams hi_streams = EncodeAt(gop, yuv, sup, o.kernel, levels, hi, &hi_rec);
    for (int it = 0; it < 10; ++it) {
      const double mid = 0.5 * (lo + hi);
      PredictiveDecoded mid_rec;
      PredictiveStreams mid_streams = EncodeAt(gop, yuv, sup, o.kernel, levels, mid, &mid_rec);
      if (mid_streams.Bytes() <= o.target_bytes) {
        hi = mid, hi_streams = std::move(mid_streams), hi_rec = std::move(mid_rec);
      } else {
        lo = mid;
      }
    }
    best = std::move(hi_streams);
    rec = std::move(hi_rec);
  }
  if (reconstruction) {
    *reconstruction = std::move(rec);
    AssembleRgb(gop, reconstruction);
  }
  return best;
}

}  // namespace fvv
