#include <algorithm>

#include "codec/bisk.h"
#include "codec/colour.h"
#include "codec/predictive_texture.h"
#include "codec/predictive_texture_common.h"

namespace fvv {

uint64_t PredictiveStreams::Bytes() const {
  uint64_t n = 0;
  for (const std::vector<uint8_t>* s : Ordered()) n += s->size();
  return n;
}

std::vector<const std::vector<uint8_t>*> PredictiveStreams::Ordered() const {
  std::vector<const std::vector<uint8_t>*> out;
  out.reserve(3 * (1 + r0.size() + r.size()));
  for (const auto& s : t00) out.push_back(&s);
  for (const auto* set : {&r0, &r}) {
    for (const ChannelStreams& c : *set) {
      for (const auto& s : c) out.push_back(&s);
    }
  }
  return out;
}

std::vector<std::vector<uint8_t>*> PredictiveStreams::Ordered() {
  std::vector<std::vector<uint8_t>*> out;
  for (const std::vector<uint8_t>* s : static_cast<const PredictiveStreams*>(this)->Ordered()) {
    out.push_back(const_cast<std::vector<uint8_t>*>(s));
  }
  return out;
}

void PredictiveStreams::Resize(uint32_t frames, uint32_t cameras) {
  for (auto& s : t00) s.clear();
  r0.assign(frames, {});
  r.assign(size_t(frames) * cameras, {});
}

SignalShape MakeSignalShape(std::vector<uint8_t> mask, uint32_t width, uint32_t height,
                            int levels) {
  SignalShape s;
  s.stages = ShapeAdaptiveMasks(mask, width, height, levels);
  s.mask = std::move(mask);
  return s;
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

std::vector<int32_t> DecodeSignal(const uint8_t* data, size_t size, WaveletKernel kernel,
                                  int levels, uint32_t width, uint32_t height,
                                  const SignalShape& shape, Status* status) {
  ShapePlane p;
  p.width = width, p.height = height, p.mask = shape.mask;
  const Status s = BiskDecode(data, size, kernel, levels, &p, nullptr, &shape.stages);
  if (!s.ok() && status->ok()) *status = s;
  for (int32_t& v : p.samples) v = std::clamp(v, kPredictiveSignalMin, kPredictiveSignalMax);
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
                        PredictiveDecoded* out, const PredictiveDecodeOptions& options,
                        bool want_rgb) {
  const size_t texels = size_t(gop.width) * gop.height;
  const size_t views = size_t(gop.frames) * gop.cameras;
  if (gop.mask.size() != views * texels || streams.r0.size() != gop.frames ||
      streams.r.size() != views) {
    return InvalidArgument("predictive texture: streams and GOP shape disagree");
  }
  if (streams.levels != ShapeAdaptiveLevels(gop.width, gop.height)) {
    return InvalidArgument("predictive texture: levels do not follow the atlas size");
  }
  // The byte budget, shared in proportion to the streams' sizes (B.2).
  const uint64_t total = streams.Bytes();
  const auto kept = [&](const std::vector<uint8_t>& s) -> size_t {
    if (options.max_bytes == 0 || options.max_bytes >= total) return s.size();
    return size_t(uint64_t(s.size()) * options.max_bytes / total);  // < 2^32 * 2^32
  };
  const PredictiveSupports sup = MakeSupports(gop);
  const ParallelRunner& run = options.runner;
  const uint32_t w = gop.width, h = gop.height;
  const int levels = streams.levels;
  const WaveletKernel kernel = streams.kernel;
  // Each stage's signals in parallel (T00, then every R0(t), then every
  // R(t, c)); a signal's three channels share its shape's masks.
  std::vector<Status> statuses(3 + gop.frames + views, Status::Ok());
  const SignalShape all = MakeSignalShape(sup.all, w, h, levels);
  run(3, [&](uint32_t k) {
    out->t00[k] = DecodeSignal(streams.t00[k].data(), kept(streams.t00[k]), kernel, levels, w, h,
                               all, &statuses[k]);
    for (int32_t& v : out->t00[k]) v += kPredictiveLevelShift;
  });
  out->r0.assign(gop.frames, {});
  run(gop.frames, [&](uint32_t t) {
    const SignalShape shape = MakeSignalShape(sup.frame[t], w, h, levels);
    Status s = Status::Ok();
    for (int k = 0; k < 3; ++k) {
      const std::vector<uint8_t>& st = streams.r0[t][k];
      out->r0[t][k] = DecodeSignal(st.data(), kept(st), kernel, levels, w, h, shape, &s);
    }
    statuses[3 + t] = s;
  });
  out->r.assign(views, {});
  out->yuv.assign(views, {});
  run(uint32_t(views), [&](uint32_t tc) {
    const uint32_t t = tc / gop.cameras;
    const SignalShape shape = MakeSignalShape(
        std::vector<uint8_t>(gop.mask.begin() + tc * texels, gop.mask.begin() + (tc + 1) * texels),
        w, h, levels);
    Status s = Status::Ok();
    for (int k = 0; k < 3; ++k) {
      const std::vector<uint8_t>& st = streams.r[tc][k];
      out->r[tc][k] = DecodeSignal(st.data(), kept(st), kernel, levels, w, h, shape, &s);
      std::vector<int32_t>& yuv = out->yuv[tc][k];
      yuv.resize(texels);
      const int32_t* a = out->t00[k].data();
      const int32_t* b = out->r0[t][k].data();
      const int32_t* c = out->r[tc][k].data();
      for (size_t i = 0; i < texels; ++i) yuv[i] = PredictiveSample(a[i], b[i], c[i]);
    }
    statuses[3 + gop.frames + tc] = s;
  });
  for (const Status& s : statuses) FVV_RETURN_IF_ERROR(s);
  if (want_rgb) AssembleRgb(gop, out);
  return Status::Ok();
}

}  // namespace fvv
