// The encoder session's GOP coding: a span of frames' atlas textures into one
// fragment per camera group (the 4D wavelet coders or the predictive scheme),
// with its masks, motion and the running error figures.
#include "encoder/encode/encoder_session.h"

namespace fvv {
namespace encoding {

Status Session::CodeSpan(uint32_t frames) {
  if (static_ && AppliesFills()) ApplyFallback(frames);
  if (!span_usable_.empty()) FillForPlayers(frames);
  const uint32_t span_first = first_ + uint32_t(fragments_.size() / CameraGroups()) * s_.gop_frames;
  // Saved as coded (fallback texels included), so other codecs compared on
  // them code the same content, and --textures encodes them again.
  if (!s_.save_textures.empty()) {
    for (uint32_t t = 0; t < frames; ++t) FVV_RETURN_IF_ERROR(SaveTextures(span_first + t, t));
  }
  const auto t0 = Clock::now();
  // The camera groups are coded side by side: with many cameras in groups of
  // one, each block is too small to keep the pool busy on its own. Each group's
  // figures are added in group order, so the summary does not depend on the
  // threads.
  const uint32_t groups = CameraGroups();
  std::vector<FragmentData> coded(groups);
  std::vector<GroupFigures> figures(groups);
  std::vector<Status> status(groups);
  pool_.Run(groups, [&](uint32_t g) {
    status[g] = CodeGroup(g, frames, span_first, &coded[g], &figures[g]);
  });
  for (uint32_t g = 0; g < groups; ++g) {
    FVV_RETURN_IF_ERROR(status[g]);
    for (int c = 0; c < 3; ++c) {
      sse_[c] += figures[g].sse[c];
      samples_[c] += figures[g].samples[c];
    }
    sse_rgb_ += figures[g].sse_rgb;
    sum_.visible_texels += figures[g].visible_texels;
    sum_.texture_bytes += figures[g].texture_bytes;
    sum_.mask_bytes += figures[g].mask_bytes;
    sum_.surface_bytes += figures[g].surface_bytes;
    fragments_.push_back(std::move(coded[g]));
  }
  sum_.code_s += Since(t0);
  return Status::Ok();
}

Status Session::CodeGroup(uint32_t g, uint32_t frames, uint32_t span_first, FragmentData* out,
                          GroupFigures* figures) const {
  const size_t texels = size_t(s_.atlas_size) * s_.atlas_size;
  FragmentData& frag = *out;
  frag.info.gop_index = uint32_t(fragments_.size() + g);
  frag.info.first_frame = span_first - first_;
  frag.info.frame_count = uint16_t(frames);
  frag.info.first_camera = uint16_t(g * s_.gop_cameras);
  frag.info.camera_count =
      uint16_t(std::min<uint32_t>(s_.gop_cameras, sum_.cameras - g * s_.gop_cameras));
  if (g == 0 && !span_surface_.empty()) {
    // The span's surface rides in the first camera group, beside the motion.
    const uint32_t vertices = uint32_t(model_.mesh.positions.size());
    std::vector<int32_t> values;
    values.reserve(size_t(frames) * vertices);
    for (uint32_t t = 0; t < frames; ++t) {
      values.insert(values.end(), span_surface_[t].begin(), span_surface_[t].end());
    }
    frag.has_surface = true;
    frag.surface_head.step_exponent = s_.surface_step_exponent;
    frag.surface_head.vertex_count = vertices;
    frag.surface = EncodeSurfaceDisplacements(values, frames, vertices);
    frag.surface_head.data_size = uint32_t(frag.surface.size());
    figures->surface_bytes = frag.surface.size();
  }
  Shape4D shape;
  shape.n = {frames, frag.info.camera_count, s_.atlas_size, s_.atlas_size};
  std::vector<uint8_t> rgb(shape.count() * 3);
  // `seen`: what the cameras saw (the masks); `used`: what a player will
  // show, which the coder fills around and weights (without masks, also
  // what the geometry lets a player take from a camera).
  UsedMask seen(shape.count());
  for (uint32_t t = 0; t < frames; ++t) {
    for (uint32_t c = 0; c < frag.info.camera_count; ++c) {
      const size_t src = size_t(t) * sum_.cameras + frag.info.first_camera + c;
      const size_t dst = size_t(t) * frag.info.camera_count + c;
      std::copy_n(&span_rgb_[src * texels * 3], texels * 3, &rgb[dst * texels * 3]);
      std::copy_n(&span_mask_[src * texels], texels, &seen[dst * texels]);
    }
  }
  UsedMask used = seen;
  if (!span_usable_.empty()) {
    for (uint32_t t = 0; t < frames; ++t) {
      for (uint32_t c = 0; c < frag.info.camera_count; ++c) {
        const size_t src = (size_t(t) * sum_.cameras + frag.info.first_camera + c) * texels;
        const size_t dst = (size_t(t) * frag.info.camera_count + c) * texels;
        for (size_t i = 0; i < texels; ++i) used[dst + i] |= span_usable_[src + i];
      }
    }
  }
  const Block block = BlockFromRgb(rgb.data(), shape, ColourSpace::kYCbCr601, s_.chroma,
                                   SampleFrac(), &used, ChromaUpsamplingOf());
  if (s_.texture_codec == TextureCodec::kPredictive) {
    return CodePredictive(block, rgb, used, shape, &frag, figures);
  }
  EncodeSettings es;
  es.kernel = s_.kernel;
  es.frac_bits_97 = s_.frac_bits_97;
  es.coder = s_.coder;
  es.weights = s_.weights;
  es.rate_mode = s_.rate_mode;
  es.rate_value = s_.rate_value;
  es.fill = s_.fill;
  es.prune_isolated = s_.prune_isolated;
  // A PSNR target is over what the cameras saw, masks or not.
  if (!span_usable_.empty()) es.psnr_mask = &seen;
  es.runner = pool_.runner();
  Block decoded;
  EncodeReport report;
  report.decoded = &decoded;  // what a decoder reconstructs at full length
  FVV_ASSIGN_OR_RETURN(frag.texture, EncodeBlock(block, &used, es, &report));
  decoded.upsampling = block.upsampling;  // a stream-level rule, not in the block's syntax
  if (s_.masks) {
    frag.masks = EncodeMasks(used.data(), shape, s_.mask_coding);
    frag.mask_mode = s_.mask_coding;
  }
  figures->texture_bytes = frag.texture.total_bytes();
  figures->mask_bytes = frag.masks.size();
  Measure(block, decoded, seen, rgb, figures);
  return Status::Ok();
}

// One GOP with the predictive scheme; the same rate targets as SPIHT's.
Status Session::CodePredictive(const Block& block, std::vector<uint8_t>& rgb, const UsedMask& used,
                               const Shape4D& shape, FragmentData* frag,
                               GroupFigures* figures) const {
  PredictiveGop gop;
  gop.frames = shape.frames(), gop.cameras = shape.cameras();
  gop.width = shape.width(), gop.height = shape.height();
  gop.rgb = std::move(rgb);
  gop.mask = used;
  PredictiveEncodeOptions o;
  o.kernel = s_.kernel;
  o.runner = pool_.runner();
  if (s_.rate_mode == RateMode::kPsnr) {
    o.target_psnr = s_.rate_value;
  } else if (s_.rate_mode == RateMode::kTotalBytes) {
    o.target_bytes = uint64_t(s_.rate_value);
  } else if (s_.rate_mode == RateMode::kBitsPerSample) {
    o.target_bytes = uint64_t(std::ceil(s_.rate_value * double(shape.count()) / 8));
  }
  PredictiveDecoded rec;
  FVV_ASSIGN_OR_RETURN(frag->predictive_texture, EncodePredictive(gop, o, &rec));
  frag->predictive = true;
  frag->masks = EncodeMasks(used.data(), shape, s_.mask_coding);
  frag->mask_mode = s_.mask_coding;
  figures->texture_bytes = frag->predictive_texture.Bytes();
  figures->mask_bytes = frag->masks.size();
  Block decoded = block;
  const size_t texels = size_t(gop.width) * gop.height;
  for (int k = 0; k < 3; ++k) {
    for (size_t tc = 0; tc < rec.yuv.size(); ++tc) {
      std::copy(rec.yuv[tc][k].begin(), rec.yuv[tc][k].end(),
                decoded.channels[k].samples.begin() + tc * texels);
    }
  }
  Measure(block, decoded, used, gop.rgb, figures);
  return Status::Ok();
}

// Y, U, V errors against the block coded; RGB errors against the texels as
// resampled (what a player shows against what the cameras saw).
void Session::Measure(const Block& block, const Block& decoded, const UsedMask& used,
                      const std::vector<uint8_t>& a,
                      GroupFigures* figures) const {  // `used`: what the cameras saw
  UsedMask chroma_used;
  const UsedMask* cmask = &used;
  if (block.chroma == ChromaFormat::k420) {
    chroma_used = DownsampleMask(used, block.shape(), block.channels[1].shape);
    cmask = &chroma_used;
  }
  for (int c = 0; c < 3; ++c) {
    const UsedMask& m = c == 0 ? used : *cmask;
    uint64_t count = 0;
    for (uint8_t u : m) count += u != 0;
    figures->sse[c] +=
        ChannelMse(block.channels[c], decoded.channels[c], &m, block.sample_frac) * count;
    figures->samples[c] += count;
  }
  std::vector<uint8_t> b(a.size());
  BlockToRgb(decoded, b.data());
  for (size_t i = 0; i < used.size(); ++i) {
    if (!used[i]) continue;
    ++figures->visible_texels;
    for (int k = 0; k < 3; ++k) {
      const double d = double(a[3 * i + k]) - b[3 * i + k];
      figures->sse_rgb += d * d;
    }
  }
}

}  // namespace encoding
}  // namespace fvv
