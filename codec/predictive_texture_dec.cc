#include "codec/bisk.h"
#include "codec/colour.h"
#include "codec/predictive_texture.h"
#include "codec/predictive_texture_support.h"

namespace fvv {

uint64_t PredictiveStreams::Bytes() const {
  uint64_t n = 0;
  for (const auto& s : t00) n += s.size();
  for (const auto& set : {&r0, &r}) {
    for (const ChannelStreams& c : *set) {
      for (const auto& s : c) n += s.size();
    }
  }
  return n;
}

PredictiveSupports MakeSupports(const PredictiveGop& gop) {
  const size_t texels = size_t(gop.width) * gop.height;
  PredictiveSupports s;
  s.all.assign(texels, 0);
  s.frame.assign(gop.frames, std::vector<uint8_t>(texels, 0));
  for (uint32_t t = 0; t < gop.frames; ++t) {
    for (uint32_t c = 0; c < gop.cameras; ++c) {
      const uint8_t* m = &gop.mask[(size_t(t) * gop.cameras + c) * texels];
      for (size_t i = 0; i < texels; ++i) {
        if (m[i]) s.frame[t][i] = 1, s.all[i] = 1;
      }
    }
  }
  return s;
}

std::vector<int32_t> DecodeSignal(const std::vector<uint8_t>& stream, WaveletKernel kernel,
                                  int levels, uint32_t width, uint32_t height,
                                  const std::vector<uint8_t>& shape, Status* status) {
  ShapePlane p;
  p.width = width, p.height = height, p.mask = shape;
  const Status s = BiskDecode(stream.data(), stream.size(), kernel, levels, &p);
  if (!s.ok() && status->ok()) *status = s;
  return p.samples;
}

void AssembleRgb(const PredictiveGop& gop, PredictiveDecoded* out) {
  const size_t texels = size_t(gop.width) * gop.height;
  out->rgb.assign(size_t(gop.frames) * gop.cameras * texels * 3, 0);
  for (size_t tc = 0; tc < size_t(gop.frames) * gop.cameras; ++tc) {
    const uint8_t* m = &gop.mask[tc * texels];
    for (size_t i = 0; i < texels; ++i) {
      if (!m[i]) continue;
      const Rgb8 rgb = YuvToRgb(ColourSpace::kYCbCr601, out->yuv[tc][0][i], out->yuv[tc][1][i],
                                out->yuv[tc][2][i]);
      uint8_t* o = &out->rgb[(tc * texels + i) * 3];
      o[0] = rgb.r, o[1] = rgb.g, o[2] = rgb.b;
    }
  }
}

Status DecodePredictive(const PredictiveStreams& streams, const PredictiveGop& gop,
                        PredictiveDecoded* out) {
  const size_t texels = size_t(gop.width) * gop.height;
  const size_t views = size_t(gop.frames) * gop.cameras;
  if (gop.mask.size() != views * texels || streams.r0.size() != gop.frames ||
      streams.r.size() != views) {
    return InvalidArgument("predictive texture: streams and GOP shape disagree");
  }
  const PredictiveSupports sup = MakeSupports(gop);
  Status status = Status::Ok();
  out->r0.assign(gop.frames, {});
  out->r.assign(views, {});
  out->yuv.assign(views, {});
  for (int k = 0; k < 3; ++k) {
    out->t00[k] = DecodeSignal(streams.t00[k], streams.kernel, streams.levels, gop.width,
                               gop.height, sup.all, &status);
    for (size_t i = 0; i < texels; ++i) {
      if (sup.all[i]) out->t00[k][i] += kPredictiveLevelShift;
    }
    for (uint32_t t = 0; t < gop.frames; ++t) {
      out->r0[t][k] = DecodeSignal(streams.r0[t][k], streams.kernel, streams.levels, gop.width,
                                   gop.height, sup.frame[t], &status);
      for (uint32_t c = 0; c < gop.cameras; ++c) {
        const size_t tc = size_t(t) * gop.cameras + c;
        const std::vector<uint8_t> shape(gop.mask.begin() + tc * texels,
                                         gop.mask.begin() + (tc + 1) * texels);
        out->r[tc][k] = DecodeSignal(streams.r[tc][k], streams.kernel, streams.levels, gop.width,
                                     gop.height, shape, &status);
        std::vector<int32_t>& yuv = out->yuv[tc][k];
        yuv.assign(texels, 0);
        for (size_t i = 0; i < texels; ++i) {
          if (shape[i]) yuv[i] = out->t00[k][i] + out->r0[t][k][i] + out->r[tc][k][i];
        }
      }
    }
  }
  if (!status.ok()) return status;
  AssembleRgb(gop, out);
  return Status::Ok();
}

}  // namespace fvv
