// EncodeBlock: fill, transform, quantise, SPIHT per channel, rate allocation.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>

#include "codec/block_codec.h"
#include "codec/fill.h"
#include "codec/spiht4d.h"
#include "codec/subband_weights.h"

namespace fvv {
namespace {

// Applies fn(index, band_id) to every coefficient, walking the per-axis band codes.
template <typename Fn>
void ForEachBand(const WaveletGeometry& g, Fn fn) {
  const auto& n = g.shape.n;
  size_t i = 0;
  std::array<uint8_t, kAxes> codes;
  for (uint32_t t = 0; t < n[0]; ++t) {
    codes[0] = g.axis[0].band[t];
    for (uint32_t c = 0; c < n[1]; ++c) {
      codes[1] = g.axis[1].band[c];
      for (uint32_t y = 0; y < n[2]; ++y) {
        codes[2] = g.axis[2].band[y];
        for (uint32_t x = 0; x < n[3]; ++x, ++i) {
          codes[3] = g.axis[3].band[x];
          fn(i, SubbandQuantisers::BandId(codes));
        }
      }
    }
  }
}

struct ChannelRd {
  std::vector<uint64_t> bytes;
  std::vector<double> distortion;  // weighted
};

// Lower convex hull of a decreasing RD curve (bytes ascending).
ChannelRd ConvexHull(const std::vector<uint64_t>& bytes, const std::vector<double>& d, double w) {
  ChannelRd hull;
  for (size_t i = 0; i < bytes.size(); ++i) {
    const double di = d[i] * w;
    if (!hull.bytes.empty() && bytes[i] <= hull.bytes.back()) {
      if (di < hull.distortion.back()) hull.distortion.back() = di;
      continue;
    }
    if (!hull.distortion.empty() && di >= hull.distortion.back()) continue;
    while (hull.bytes.size() >= 2) {
      const size_t k = hull.bytes.size();
      const double s_prev = (hull.distortion[k - 2] - hull.distortion[k - 1]) /
                            static_cast<double>(hull.bytes[k - 1] - hull.bytes[k - 2]);
      const double s_new =
          (hull.distortion[k - 1] - di) / static_cast<double>(bytes[i] - hull.bytes[k - 1]);
      if (s_new < s_prev) break;
      hull.bytes.pop_back();
      hull.distortion.pop_back();
    }
    hull.bytes.push_back(bytes[i]);
    hull.distortion.push_back(di);
  }
  return hull;
}

// Greedy allocation over hull segments in order of slope. Stops when `budget`
// bytes are spent or the total distortion reaches `target` (whichever first);
// the last segment is taken in part (streams are embedded, any cut decodes).
std::array<uint64_t, 3> Allocate(const std::array<ChannelRd, 3>& hulls, uint64_t budget,
                                 double target, double* final_distortion) {
  std::array<uint64_t, 3> alloc{0, 0, 0};
  std::array<size_t, 3> seg{0, 0, 0};
  double total_d = 0;
  for (const auto& h : hulls) total_d += h.distortion.empty() ? 0 : h.distortion[0];
  uint64_t spent = 0;
  while (spent < budget && total_d > target) {
    int best = -1;
    double best_slope = -1;
    for (int c = 0; c < 3; ++c) {
      const ChannelRd& h = hulls[c];
      if (seg[c] + 1 >= h.bytes.size()) continue;
      const double slope = (h.distortion[seg[c]] - h.distortion[seg[c] + 1]) /
                           static_cast<double>(h.bytes[seg[c] + 1] - h.bytes[seg[c]]);
      if (slope > best_slope) {
        best_slope = slope;
        best = c;
      }
    }
    if (best < 0) break;
    const ChannelRd& h = hulls[best];
    const uint64_t seg_bytes = h.bytes[seg[best] + 1] - h.bytes[seg[best]];
    const double seg_gain = h.distortion[seg[best]] - h.distortion[seg[best] + 1];
    uint64_t take = std::min(seg_bytes, budget - spent);
    if (total_d - seg_gain < target) {
      take = std::min<uint64_t>(take,
                                static_cast<uint64_t>(std::ceil((total_d - target) / best_slope)));
    }
    alloc[best] += take;
    spent += take;
    total_d -= best_slope * static_cast<double>(take);
    if (take < seg_bytes) break;
    ++seg[best];
  }
  if (final_distortion) *final_distortion = total_d;
  return alloc;
}

void CutStream(uint64_t bytes, ChannelStream* s) {
  if (s->data.size() > bytes) s->data.resize(bytes);
  while (!s->points.empty() && s->points.back().bytes > s->data.size()) s->points.pop_back();
  while (!s->rd.empty() && s->rd.back().bytes > s->data.size()) s->rd.pop_back();
}

EncodedBlock CutBlock(const EncodedBlock& full, const std::array<uint64_t, 3>& alloc) {
  EncodedBlock out = full;
  for (int c = 0; c < 3; ++c) CutStream(alloc[c], &out.channels[c]);
  return out;
}

// Encoder-side pruning: a coefficient that would turn significant only in the
// lowest bitplane a cut stream reaches, with none of its 8 neighbours in the
// plane (x +- 1, y +- 1) significant by then, costs SPIHT the set splits that
// isolate it, a significance, a sign and refinements for one coefficient's
// worth of error. Zeroing such coefficients and coding again moves those
// bytes to coefficients that come in clusters (docs/encoder.md, "Pruning").
// Roots are kept. Returns the weighted energy zeroed (the quantisers' distortion
// factors times the squared magnitudes, as the SPIHT encoder counts error).
double PruneIsolated(const SpihtTree& tree, const SubbandQuantisers& q, const ChannelStream& cut,
                     std::vector<int32_t>* coeffs) {
  int lowest = cut.planes - 1;  // the plane of the pass the cut falls in
  if (!cut.points.empty()) {
    const TruncationPoint& last = cut.points.back();
    lowest = last.pass == 1 ? last.plane - 1 : last.plane;
  }
  if (lowest < 0) return 0;
  const int32_t lo = int32_t{1} << lowest, hi = int32_t{1} << (lowest + 1);
  std::vector<int32_t>& c = *coeffs;
  const size_t w = tree.geometry().shape.width();
  auto big = [&](size_t j) { return c[j] >= lo || c[j] <= -lo; };
  std::vector<uint32_t> pruned;
  double energy = 0;
  ForEachBand(tree.geometry(), [&](size_t i, int band) {
    const uint32_t idx = static_cast<uint32_t>(i);
    const int32_t m = c[i] < 0 ? -c[i] : c[i];
    if (m < lo || m >= hi || tree.LevelClass(idx) == 0) return;
    const bool left = tree.HasLeft(idx), right = tree.HasRight(idx), up = tree.HasUp(idx),
               down = tree.HasDown(idx);
    if ((left && big(i - 1)) || (right && big(i + 1)) || (up && big(i - w)) ||
        (down && big(i + w)) || (left && up && big(i - w - 1)) || (right && up && big(i - w + 1)) ||
        (left && down && big(i + w - 1)) || (right && down && big(i + w + 1)))
      return;
    pruned.push_back(idx);
    energy += q[band].distortion * double(m) * double(m);
  });
  // Zeroed after the scan, so that each test sees the coefficients as they were.
  for (uint32_t i : pruned) c[i] = 0;
  return energy;
}

double WeightedMse(const Block& a, const Block& b, const UsedMask* mask,
                   const std::array<double, 3>& w) {
  UsedMask chroma_mask;
  const UsedMask* cmask = mask;
  if (mask && a.chroma == ChromaFormat::k420) {
    chroma_mask = DownsampleMask(*mask, a.shape(), a.channels[1].shape);
    cmask = &chroma_mask;
  }
  double sum = 0, wsum = 0;
  for (int c = 0; c < 3; ++c) {
    sum += w[c] * ChannelMse(a.channels[c], b.channels[c], c == 0 ? mask : cmask, a.sample_frac);
    wsum += w[c];
  }
  return sum / wsum;
}

}  // namespace

StatusOr<EncodedBlock> EncodeBlock(const Block& block, const UsedMask* mask,
                                   const EncodeSettings& settings, EncodeReport* report) {
  EncodedBlock out;
  if (settings.kernel == WaveletKernel::kCdf97 && !ValidFracBits97(settings.frac_bits_97))
    return InvalidArgument("9/7 sample precision must be " + std::to_string(kMinFracBits97) + ".." +
                           std::to_string(kMaxFracBits97) + " fractional bits");
  out.params = {block.shape(), settings.kernel, settings.coder, block.colour, block.chroma};
  out.params.frac_bits =
      static_cast<uint8_t>(KernelFracBits(settings.kernel, settings.frac_bits_97));
  out.params.weights = settings.weights;
  out.params.sample_frac = block.sample_frac;
  if (block.sample_frac > std::min<int>(kMaxSampleFrac, out.params.frac_bits))
    return InvalidArgument("a block with " + std::to_string(block.sample_frac) +
                           " fractional bits per sample needs the 9/7 kernel with at least as "
                           "many fractional bits in the transform (and at most " +
                           std::to_string(kMaxSampleFrac) + ")");
  if (block.sample_frac > 0 && block.colour == ColourSpace::kRct)
    return InvalidArgument("RCT blocks take whole samples (sample_frac 0)");
  if (block.sample_frac > 0 && settings.weights != BandWeights::kOwnBand)
    return InvalidArgument(
        "fractional samples need own-band weights (format version 7 extends version 6)");
  FVV_RETURN_IF_ERROR(ValidateParams(out.params));
  if (block.channels[1].shape != ChromaShape(block.shape(), block.chroma) ||
      block.channels[2].shape != block.channels[1].shape)
    return InvalidArgument("chroma planes do not match the chroma format");
  for (const Plane4D& p : block.channels)
    if (p.samples.size() != p.shape.count()) return InvalidArgument("plane size mismatch");
  if (mask && mask->size() != block.shape().count())
    return InvalidArgument("mask has " + std::to_string(mask->size()) + " entries, block has " +
                           std::to_string(block.shape().count()) + " texels");
  if (settings.psnr_mask && settings.psnr_mask->size() != block.shape().count())
    return InvalidArgument("the PSNR mask has " + std::to_string(settings.psnr_mask->size()) +
                           " entries, block has " + std::to_string(block.shape().count()) +
                           " texels");
  if (settings.rate_mode == RateMode::kLossless &&
      (settings.kernel == WaveletKernel::kCdf97 || block.colour != ColourSpace::kRct ||
       block.chroma != ChromaFormat::k444))
    return InvalidArgument("lossless coding needs the haar or 53 kernel, RCT colour and 4:4:4");
  if (settings.rate_mode != RateMode::kLossless && !(settings.rate_value > 0))
    return InvalidArgument("rate target must be positive");

  const uint64_t samples = block.shape().count();
  uint64_t cap = UINT64_MAX;
  if (settings.rate_mode == RateMode::kBitsPerSample)
    cap = static_cast<uint64_t>(std::ceil(settings.rate_value * static_cast<double>(samples) / 8));
  else if (settings.rate_mode == RateMode::kTotalBytes)
    cap = static_cast<uint64_t>(settings.rate_value);
  else if (settings.rate_mode == RateMode::kPsnr)
    cap = std::max<uint64_t>(64, samples / 32);  // 0.25 bpp per channel first; grown below
  cap = std::max<uint64_t>(cap, 1);
  // Share of texels used: the transform-domain error estimate covers all
  // texels, the PSNR target only the used ones (where the error concentrates).
  double used_share = 1;
  if (mask) {
    uint64_t used = 0;
    for (uint8_t u : *mask) used += u != 0;
    used_share = std::max(1.0, double(used)) / double(samples);
  }

  // Transform and code each channel.
  const int frac = out.params.frac_bits;
  std::array<std::vector<uint64_t>, 3> rd_bytes;
  std::array<std::vector<double>, 3> rd_distortion;
  std::array<std::vector<int32_t>, 3> coeffs;
  // In 4:2:0 the chroma planes share one mask at their resolution.
  UsedMask chroma_mask;
  if (mask && block.chroma != ChromaFormat::k444)
    chroma_mask = DownsampleMask(*mask, block.shape(), block.channels[1].shape);
  for (int c = 0; c < 3; ++c) {
    const SampleRange range = ChannelRange(block.colour, c, block.sample_frac);
    Plane4D plane = block.channels[c];
    if (mask) {
      const UsedMask& m = c == 0 || chroma_mask.empty() ? *mask : chroma_mask;
      FillUnused(m, range.offset, &plane, settings.fill.pull);
      SparseFill(settings.kernel, m, range, settings.fill, settings.runner, &plane);
    }
    // Samples with p fractional bits enter the transform with frac - p more.
    for (int32_t& s : plane.samples) s = (s - range.offset) * (1 << (frac - block.sample_frac));
    const WaveletGeometry g(plane.shape);
    ForwardTransform4D(settings.kernel, g, settings.runner, plane.samples.data());
    const SubbandQuantisers q(settings.kernel, frac, settings.weights, g);
    ForEachBand(g, [&](size_t i, int band) {
      plane.samples[i] = QuantiseCoefficient(plane.samples[i], q[band].mul_q16);
    });
    coeffs[c] = std::move(plane.samples);
  }
  std::array<ChannelRd, 3> hulls;
  double wsum = 0;
  for (int c = 0; c < 3; ++c) wsum += settings.channel_weights[c];
  // The PSNR mode's target as a mean squared error per used texel.
  const double target_mse = 255.0 * 255.0 / std::pow(10.0, settings.rate_value / 10.0);
  // Distortion per luma sample, as the allocation weighs it.
  const double per_sample = 1.0 / static_cast<double>(samples);
  // SPIHT-codes every channel's coefficients up to `cap` bytes and builds the
  // weighted RD hulls the rate allocation across channels works on; true if a
  // channel reached the cap.
  auto code_channels = [&]() {
    settings.runner(3, [&](uint32_t c) {
      const WaveletGeometry g(block.channels[c].shape);
      const std::shared_ptr<const SpihtTree> tree = SharedSpihtTree(g);
      const SubbandQuantisers q(settings.kernel, frac, settings.weights, g);
      SpihtEncoded enc = SpihtEncode(*tree, q, coeffs[c], settings.coder, cap);
      out.channels[c].planes = enc.planes;
      out.channels[c].data = std::move(enc.data);
      out.channels[c].points = std::move(enc.points);
      rd_bytes[c] = std::move(enc.rd_bytes);
      rd_distortion[c] = std::move(enc.rd_distortion);
    });
    bool capped = false;
    for (int c = 0; c < 3; ++c) {
      hulls[c] =
          ConvexHull(rd_bytes[c], rd_distortion[c], settings.channel_weights[c] * per_sample);
      capped = capped || out.channels[c].data.size() >= cap;
      std::vector<RdPoint>& rd = out.channels[c].rd;
      rd.clear();
      for (size_t k = 0; k < hulls[c].bytes.size(); ++k) {
        rd.push_back({hulls[c].bytes[k], hulls[c].distortion[k]});
      }
    }
    return capped;
  };
  for (;;) {
    const bool capped = code_channels();
    if (settings.rate_mode != RateMode::kPsnr || !capped || cap >= samples) break;
    // A PSNR target: code only as deep as it needs (SPIHT's cost grows with the
    // bytes it writes). The estimate's error spreads over all texels, the
    // target's over the used ones; the search below needs room beyond
    // the estimate.
    const std::array<uint64_t, 3> guess =
        Allocate(hulls, UINT64_MAX, target_mse * wsum * std::sqrt(used_share), nullptr);
    uint64_t need = 0;
    for (int c = 0; c < 3; ++c) {
      if (out.channels[c].data.size() >= cap) need = std::max(need, guess[c] + guess[c] / 4 + 64);
    }
    if (need <= cap) break;
    cap = std::min<uint64_t>(samples, std::max(need, cap * 2));
  }
  double final_d = 0;
  if (settings.rate_mode == RateMode::kBitsPerSample ||
      settings.rate_mode == RateMode::kTotalBytes) {
    EncodedBlock cut = CutBlock(out, Allocate(hulls, cap, 0.0, &final_d));
    if (settings.prune_isolated) {
      // Kept only where a decode shows less error at the same bytes: where
      // isolated coefficients are the content (noise, fine texture), zeroing
      // them costs more than the bytes it frees buy. (The transform-domain
      // estimate interpolates inside the last pass, too coarse to decide.)
      auto decoded_mse = [&](const EncodedBlock& e, Block* decoded) {
        auto dec = DecodeBlock(e, DecodeBudget{}, settings.runner);
        if (!dec.ok()) return std::numeric_limits<double>::infinity();
        *decoded = std::move(*dec);
        return WeightedMse(block, *decoded, mask, settings.channel_weights);
      };
      // Zeroes the isolated coefficients of each channel the cut truncates.
      double added = 0;  // the weighted error that adds per sample, outside the RD curves
      for (int c = 0; c < 3; ++c) {
        if (cut.channels[c].data.size() >= out.channels[c].data.size()) continue;  // not cut
        const WaveletGeometry g(block.channels[c].shape);
        const SubbandQuantisers q(settings.kernel, frac, settings.weights, g);
        added += settings.channel_weights[c] * per_sample *
                 PruneIsolated(*SharedSpihtTree(g), q, cut.channels[c], &coeffs[c]);
      }
      if (added > 0) {  // nothing zeroed: coding again would give the same streams
        Block plain_decoded, pruned_decoded;
        const double plain_mse = decoded_mse(cut, &plain_decoded);
        code_channels();
        double pruned_d = 0;
        EncodedBlock pruned = CutBlock(out, Allocate(hulls, cap, 0.0, &pruned_d));
        const bool keep = decoded_mse(pruned, &pruned_decoded) < plain_mse;
        if (keep) cut = std::move(pruned), final_d = pruned_d + added;
        if (report && report->decoded) {
          *report->decoded = std::move(keep ? pruned_decoded : plain_decoded);
          report->decoded_filled = true;
        }
      }
    }
    out = std::move(cut);
  } else if (settings.rate_mode == RateMode::kPsnr) {
    // The estimate gives a starting point; actual decodes over used texels settle it.
    Block trial_decoded, best_decoded;
    auto psnr_at = [&](uint64_t budget, EncodedBlock* cut) {
      *cut = CutBlock(out, Allocate(hulls, budget, 0.0, nullptr));
      auto dec = DecodeBlock(*cut, DecodeBudget{}, settings.runner);
      if (!dec.ok()) return 0.0;
      trial_decoded = std::move(*dec);
      return PsnrFromMse(WeightedMse(block, trial_decoded,
                                     settings.psnr_mask ? settings.psnr_mask : mask,
                                     settings.channel_weights));
    };
    // First guess: the transform-domain estimate, whose error spreads over all
    // texels while the target counts the used ones.
    const std::array<uint64_t, 3> guess =
        Allocate(hulls, UINT64_MAX, target_mse * wsum * std::sqrt(used_share), &final_d);
    uint64_t hi = 0;
    for (int c = 0; c < 3; ++c) hi += out.channels[c].data.size();
    // Then a secant search on PSNR against log2(bytes), a near-straight line
    // at these rates: usually two or three trial decodes, not a bisection's ten.
    uint64_t bytes =
        std::clamp<uint64_t>(guess[0] + guess[1] + guess[2], 16, std::max<uint64_t>(16, hi));
    EncodedBlock best, trial;
    uint64_t best_bytes = 0;
    double p = psnr_at(bytes, &trial), slope = 3.0, prev_p = 0;
    uint64_t prev_bytes = 0;
    for (int it = 0; it < 8; ++it) {
      if (p >= settings.rate_value && (best_bytes == 0 || bytes < best_bytes)) {
        best = trial, best_bytes = bytes;
        best_decoded = std::move(trial_decoded);
        if (p - settings.rate_value < 0.1) break;
      }
      if (p < settings.rate_value && bytes >= hi) break;  // the whole stream falls short
      if (prev_bytes && prev_bytes != bytes && std::abs(p - prev_p) > 1e-6) {
        slope = std::clamp((p - prev_p) / std::log2(double(bytes) / double(prev_bytes)), 1.0, 12.0);
      }
      const double step = std::exp2((settings.rate_value + 0.03 - p) / slope);
      uint64_t next = std::clamp<uint64_t>(uint64_t(std::llround(double(bytes) * step)), 16,
                                           std::max<uint64_t>(16, hi));
      if (best_bytes) next = std::min(next, best_bytes - 1);
      if (next == bytes || next < 16) break;
      prev_bytes = bytes, prev_p = p;
      bytes = next;
      p = psnr_at(bytes, &trial);
    }
    if (best_bytes == 0) {
      best = out;  // the target is beyond the coded depth: everything coded
    } else if (report && report->decoded) {
      *report->decoded = std::move(best_decoded);
      report->decoded_filled = true;
    }
    out = std::move(best);
  }
  if (report && report->decoded && !report->decoded_filled) {
    FVV_ASSIGN_OR_RETURN(*report->decoded, DecodeBlock(out, DecodeBudget{}, settings.runner));
    report->decoded_filled = true;
  }
  if (report) {
    for (int c = 0; c < 3; ++c) report->channel_bytes[c] = out.channels[c].data.size();
    report->estimated_psnr = PsnrFromMse(final_d / wsum);
  }
  return out;
}

}  // namespace fvv
