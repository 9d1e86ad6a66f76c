// EncodeBlock: fill, transform, quantise, SPIHT per channel, rate allocation.
#include <algorithm>
#include <chrono>
#include <cmath>
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
}

EncodedBlock CutBlock(const EncodedBlock& full, const std::array<uint64_t, 3>& alloc) {
  EncodedBlock out = full;
  for (int c = 0; c < 3; ++c) CutStream(alloc[c], &out.channels[c]);
  return out;
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
    sum += w[c] * ChannelMse(a.channels[c], b.channels[c], c == 0 ? mask : cmask);
    wsum += w[c];
  }
  return sum / wsum;
}

}  // namespace

StatusOr<EncodedBlock> EncodeBlock(const Block& block, const UsedMask* mask,
                                   const EncodeSettings& settings, EncodeReport* report) {
  EncodedBlock out;
  out.params = {block.shape(), settings.kernel, settings.coder, block.colour, block.chroma};
  FVV_RETURN_IF_ERROR(ValidateParams(out.params));
  if (block.channels[1].shape != ChromaShape(block.shape(), block.chroma) ||
      block.channels[2].shape != block.channels[1].shape)
    return InvalidArgument("chroma planes do not match the chroma format");
  for (const Plane4D& p : block.channels)
    if (p.samples.size() != p.shape.count()) return InvalidArgument("plane size mismatch");
  if (mask && mask->size() != block.shape().count())
    return InvalidArgument("mask has " + std::to_string(mask->size()) + " entries, block has " +
                           std::to_string(block.shape().count()) + " texels");
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
    cap = samples;  // 8 bpp per channel: far beyond any sensible PSNR target
  cap = std::max<uint64_t>(cap, 1);

  // Transform and code each channel.
  const int frac = TransformFracBits(settings.kernel);
  std::array<std::vector<uint64_t>, 3> rd_bytes;
  std::array<std::vector<double>, 3> rd_distortion;
  std::array<std::vector<int32_t>, 3> coeffs;
  for (int c = 0; c < 3; ++c) {
    const Plane4D& src = block.channels[c];
    const SampleRange range = ChannelRange(block.colour, c);
    Plane4D plane = src;
    if (mask) {
      if (c == 0 || block.chroma == ChromaFormat::k444) {
        FillUnused(*mask, range.offset, &plane);
      } else {
        FillUnused(DownsampleMask(*mask, block.shape(), src.shape), range.offset, &plane);
      }
    }
    for (int32_t& s : plane.samples) s = (s - range.offset) * (1 << frac);
    const WaveletGeometry g(plane.shape);
    ForwardTransform4D(settings.kernel, g, settings.runner, plane.samples.data());
    const SubbandQuantisers q(settings.kernel, g);
    ForEachBand(g, [&](size_t i, int band) {
      plane.samples[i] = QuantiseCoefficient(plane.samples[i], q[band].mul_q16);
    });
    coeffs[c] = std::move(plane.samples);
  }
  settings.runner(3, [&](uint32_t c) {
    const WaveletGeometry g(block.channels[c].shape);
    const SpihtTree tree(g);
    const SubbandQuantisers q(settings.kernel, g);
    SpihtEncoded enc = SpihtEncode(tree, q, coeffs[c], settings.coder, cap);
    out.channels[c].planes = enc.planes;
    out.channels[c].data = std::move(enc.data);
    out.channels[c].points = std::move(enc.points);
    rd_bytes[c] = std::move(enc.rd_bytes);
    rd_distortion[c] = std::move(enc.rd_distortion);
  });

  // Rate allocation across channels on the weighted RD curves (distortion per luma sample).
  std::array<ChannelRd, 3> hulls;
  const double per_sample = 1.0 / static_cast<double>(samples);
  double wsum = 0;
  for (int c = 0; c < 3; ++c) {
    hulls[c] = ConvexHull(rd_bytes[c], rd_distortion[c], settings.channel_weights[c] * per_sample);
    wsum += settings.channel_weights[c];
  }
  double final_d = 0;
  if (settings.rate_mode == RateMode::kBitsPerSample ||
      settings.rate_mode == RateMode::kTotalBytes) {
    out = CutBlock(out, Allocate(hulls, cap, 0.0, &final_d));
  } else if (settings.rate_mode == RateMode::kPsnr) {
    // The estimate gives a starting point; actual decodes over used texels settle it.
    const double target_mse = 255.0 * 255.0 / std::pow(10.0, settings.rate_value / 10.0);
    auto psnr_at = [&](uint64_t budget, EncodedBlock* cut) {
      *cut = CutBlock(out, Allocate(hulls, budget, 0.0, nullptr));
      auto dec = DecodeBlock(*cut, DecodeBudget{}, settings.runner);
      return dec.ok() ? PsnrFromMse(WeightedMse(block, *dec, mask, settings.channel_weights)) : 0.0;
    };
    Allocate(hulls, UINT64_MAX, target_mse * wsum, &final_d);
    uint64_t hi = 0;
    for (int c = 0; c < 3; ++c) hi += out.channels[c].data.size();
    uint64_t lo = 0;
    EncodedBlock best = out, trial;
    if (psnr_at(hi, &trial) >= settings.rate_value) {
      best = trial;
      // Bisection on total bytes to within 0.5%.
      while (hi - lo > std::max<uint64_t>(16, hi / 200)) {
        const uint64_t mid = lo + (hi - lo) / 2;
        if (psnr_at(mid, &trial) >= settings.rate_value) {
          hi = mid;
          best = trial;
        } else {
          lo = mid;
        }
      }
    }
    out = std::move(best);
  }
  if (report) {
    for (int c = 0; c < 3; ++c) report->channel_bytes[c] = out.channels[c].data.size();
    report->estimated_psnr = PsnrFromMse(final_d / wsum);
  }
  return out;
}

}  // namespace fvv
