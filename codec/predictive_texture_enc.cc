#include <algorithm>
#include <cmath>

#include "codec/bisk.h"
#include "codec/colour.h"
#include "codec/predictive_texture.h"
#include "codec/predictive_texture_common.h"
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

// The shapes every signal is coded over, with their transform masks.
struct GopShapes {
  SignalShape all;
  std::vector<SignalShape> frame, view;
};

GopShapes MakeGopShapes(const PredictiveGop& gop, int levels, const ParallelRunner& run) {
  const size_t texels = size_t(gop.width) * gop.height;
  const size_t views = size_t(gop.frames) * gop.cameras;
  PredictiveSupports sup = MakeSupports(gop);
  GopShapes g;
  g.all = MakeSignalShape(std::move(sup.all), gop.width, gop.height, levels);
  g.frame.resize(gop.frames);
  g.view.resize(views);
  run(uint32_t(gop.frames + views), [&](uint32_t i) {
    if (i < gop.frames) {
      g.frame[i] = MakeSignalShape(sup.frame[i], gop.width, gop.height, levels);
    } else {
      const size_t tc = i - gop.frames;
      g.view[tc] = MakeSignalShape(std::vector<uint8_t>(gop.mask.begin() + tc * texels,
                                                        gop.mask.begin() + (tc + 1) * texels),
                                   gop.width, gop.height, levels);
    }
  });
  return g;
}

// The per-frame means T0(t) and the GOP mean T00 (level-shifted) of channel k.
struct Means {
  std::vector<std::vector<int32_t>> t0;
  std::vector<int32_t> t00;
};

Means MakeMeans(const PredictiveGop& gop,
                const std::vector<std::array<std::vector<int32_t>, 3>>& yuv, int k) {
  const size_t texels = size_t(gop.width) * gop.height;
  Means m;
  m.t0.assign(gop.frames, std::vector<int32_t>(texels, 0));
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
      if (count[i]) m.t0[t][i] = RoundedMean(sum[i], count[i]);
      all_sum[i] += sum[i];
      all_count[i] += count[i];
    }
  }
  m.t00.assign(texels, 0);
  for (size_t i = 0; i < texels; ++i) {
    if (all_count[i]) m.t00[i] = RoundedMean(all_sum[i], all_count[i]) - kPredictiveLevelShift;
  }
  return m;
}

// One closed-loop pass at threshold `tau`: the streams, and in `rec` what a
// decoder reconstructs from them. Within a stage (T00, the R0(t), the
// R(t, c)) signals are independent and run in parallel.
PredictiveStreams EncodeAt(const PredictiveGop& gop,
                           const std::vector<std::array<std::vector<int32_t>, 3>>& yuv,
                           const std::array<Means, 3>& means, const GopShapes& shapes,
                           WaveletKernel kernel, int levels, double tau, const ParallelRunner& run,
                           PredictiveDecoded* rec) {
  const size_t texels = size_t(gop.width) * gop.height;
  const size_t views = size_t(gop.frames) * gop.cameras;
  PredictiveStreams s;
  s.kernel = kernel;
  s.levels = levels;
  s.Resize(gop.frames, gop.cameras);
  rec->r0.assign(gop.frames, {});
  rec->r.assign(views, {});
  rec->yuv.assign(views, {});
  const auto code = [&](const std::vector<int32_t>& signal, const SignalShape& shape,
                        std::vector<uint8_t>* stream) {
    *stream = Cut(Code(signal, shape.mask, gop.width, gop.height, kernel, levels), tau);
    // The reference is what the decoder will have: the cut stream decoded.
    Status ignored = Status::Ok();
    return DecodeSignal(stream->data(), stream->size(), kernel, levels, gop.width, gop.height,
                        shape, &ignored);
  };
  run(3, [&](uint32_t k) {
    rec->t00[k] = code(means[k].t00, shapes.all, &s.t00[k]);
    for (int32_t& v : rec->t00[k]) v += kPredictiveLevelShift;
  });
  run(3 * gop.frames, [&](uint32_t i) {
    const uint32_t t = i / 3, k = i % 3;
    const std::vector<uint8_t>& support = shapes.frame[t].mask;
    std::vector<int32_t> r0(texels, 0);
    for (size_t j = 0; j < texels; ++j) {
      if (support[j]) r0[j] = means[k].t0[t][j] - rec->t00[k][j];
    }
    rec->r0[t][k] = code(r0, shapes.frame[t], &s.r0[t][k]);
  });
  run(uint32_t(3 * views), [&](uint32_t i) {
    const size_t tc = i / 3;
    const uint32_t t = uint32_t(tc / gop.cameras), k = i % 3;
    const std::vector<uint8_t>& shape = shapes.view[tc].mask;
    const int32_t* a = rec->t00[k].data();
    const int32_t* b = rec->r0[t][k].data();
    std::vector<int32_t> r(texels, 0);
    for (size_t j = 0; j < texels; ++j) {
      if (shape[j]) r[j] = yuv[tc][k][j] - (a[j] + b[j]);
    }
    rec->r[tc][k] = code(r, shapes.view[tc], &s.r[tc][k]);
    std::vector<int32_t>& out = rec->yuv[tc][k];
    out.resize(texels);
    for (size_t j = 0; j < texels; ++j) out[j] = PredictiveSample(a[j], b[j], rec->r[tc][k][j]);
  });
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
  const std::vector<std::array<std::vector<int32_t>, 3>> yuv = ToYuv(gop);
  const int levels = ShapeAdaptiveLevels(gop.width, gop.height);
  const ParallelRunner& run = o.runner;
  const GopShapes shapes = MakeGopShapes(gop, levels, run);
  std::array<Means, 3> means;
  run(3, [&](uint32_t k) { means[k] = MakeMeans(gop, yuv, int(k)); });
  const auto pass = [&](double tau, PredictiveDecoded* rec) {
    return EncodeAt(gop, yuv, means, shapes, o.kernel, levels, tau, run, rec);
  };
  // Weighted YUV PSNR over the seen texels (the SPIHT coder's PSNR target).
  const auto psnr = [&](const PredictiveDecoded& rec) {
    double sse = 0, n = 0;
    for (size_t tc = 0; tc < views; ++tc) {
      const uint8_t* m = &gop.mask[tc * texels];
      for (int k = 0; k < 3; ++k) {
        for (size_t i = 0; i < texels; ++i) {
          if (!m[i]) continue;
          const double d = double(yuv[tc][k][i]) - rec.yuv[tc][k][i];
          sse += o.channel_weights[k] * d * d;
        }
      }
      for (size_t i = 0; i < texels; ++i) n += m[i] ? 1 : 0;
    }
    const double wsum = o.channel_weights[0] + o.channel_weights[1] + o.channel_weights[2];
    const double mse = n > 0 ? sse / (n * wsum) : 0;
    return mse <= 1e-12 ? 99.0 : 10 * std::log10(255.0 * 255.0 / mse);
  };
  PredictiveDecoded rec;
  PredictiveStreams best = pass(0.0, &rec);
  // Bytes fall and the error grows as tau grows. Bisection over whole
  // closed-loop passes: for a byte target the smallest tau that fits, for a
  // PSNR target the largest that still meets it.
  const bool bytes_target = o.target_bytes > 0 && best.Bytes() > o.target_bytes;
  const bool psnr_target = o.target_psnr > 0 && o.target_bytes == 0 && psnr(rec) > o.target_psnr;
  if (bytes_target || psnr_target) {
    double good = bytes_target ? 24 : 0, bad = bytes_target ? 0 : 24;
    PredictiveDecoded good_rec;
    PredictiveStreams good_streams;
    if (bytes_target) {
      good_streams = pass(good, &good_rec);
    } else {
      good_streams = std::move(best), good_rec = std::move(rec);
    }
    for (int it = 0; it < 10; ++it) {
      const double mid = 0.5 * (good + bad);
      PredictiveDecoded mid_rec;
      PredictiveStreams mid_streams = pass(mid, &mid_rec);
      const bool ok =
          bytes_target ? mid_streams.Bytes() <= o.target_bytes : psnr(mid_rec) >= o.target_psnr;
      if (ok) {
        good = mid, good_streams = std::move(mid_streams), good_rec = std::move(mid_rec);
      } else {
        bad = mid;
      }
    }
    best = std::move(good_streams);
    rec = std::move(good_rec);
  }
  if (reconstruction) {
    *reconstruction = std::move(rec);
    AssembleRgb(gop, reconstruction);
  }
  return best;
}

}  // namespace fvv
