#include "container/fragment.h"

#include <algorithm>

#include "codec/block_syntax.h"
#include "codec/sa_wavelet.h"
#include "container/crc32c.h"
#include "container/gop_grid.h"

namespace fvv {

uint32_t TextureTools(WaveletKernel kernel, EntropyCoder coder, ColourSpace colour,
                      ChromaFormat chroma, int frac_bits, BandWeights weights, int sample_frac) {
  uint32_t tools = kernel == WaveletKernel::kHaar       ? kToolHaar
                   : kernel == WaveletKernel::kLeGall53 ? kToolLeGall53
                                                        : kToolCdf97;
  if (frac_bits != LegacyFracBits(kernel)) tools |= kToolTexturePrecision;
  if (weights == BandWeights::kOwnBand) tools |= kToolOwnBandWeights;
  if (sample_frac > 0) tools |= kToolSamplePrecision | kToolOwnBandWeights;
  tools |= coder == EntropyCoder::kQuadtree            ? kToolQuadtreeArith4
           : coder == EntropyCoder::kSetSignContexts   ? kToolSpihtArith3
           : coder == EntropyCoder::kNeighbourContexts ? kToolSpihtArith2
           : coder == EntropyCoder::kArith             ? kToolSpihtArith
                                                       : kToolSpihtBinary;
  if (chroma == ChromaFormat::k420) tools |= kToolChroma420;
  if (colour == ColourSpace::kRct) tools |= kToolReversibleColour;
  return tools;
}

uint8_t TextureVersion(uint32_t tools) {
  if (tools & kToolSamplePrecision) return 3;
  if (tools & kToolOwnBandWeights) return 2;
  return (tools & kToolTexturePrecision) ? 1 : 0;
}

uint16_t RequiredFormatVersion(uint32_t tools, MaskCoding mask_coding) {
  const uint16_t masks = (tools & kToolMasks) && mask_coding == MaskCoding::kMixing ? 2 : 1;
  return std::max(RequiredFormatVersion(tools), masks);
}

uint64_t TextureBytes(const FragmentData& f) {
  return f.predictive ? f.predictive_texture.Bytes() : f.texture.total_bytes();
}

StatusOr<FragmentInfo> FragmentInfoFor(const FileHeader& h, uint32_t gop_index) {
  const uint32_t groups = h.camera_groups();
  FragmentInfo f;
  f.gop_index = gop_index;
  const uint64_t span = gop_index / groups;
  f.first_frame = static_cast<uint32_t>(span * h.gop_frames);
  f.first_camera = static_cast<uint16_t>((gop_index % groups) * h.gop_cameras);
  if (h.frame_count != 0 && f.first_frame >= h.frame_count) {
    return InvalidArgument("fragment " + std::to_string(gop_index) +
                           " starts after the last frame");
  }
  const uint32_t frames_left = h.frame_count != 0 ? h.frame_count - f.first_frame : h.gop_frames;
  f.frame_count = static_cast<uint16_t>(std::min<uint32_t>(h.gop_frames, frames_left));
  f.camera_count =
      static_cast<uint16_t>(std::min<uint32_t>(h.gop_cameras, h.camera_count - f.first_camera));
  return f;
}

std::vector<uint8_t> WriteFragmentBox(const FragmentData& f) {
  std::vector<uint8_t> payload;
  {
    ByteWriter w;
    w.U32(f.info.gop_index);
    w.U32(f.info.first_frame);
    w.U16(f.info.frame_count);
    w.U16(f.info.first_camera);
    w.U16(f.info.camera_count);
    AppendBox(box::kFragmentHeader, 0, kBoxFlagEssential, w.bytes(), &payload);
  }
  if (!f.motion.empty()) AppendBox(box::kMotion, 0, kBoxFlagEssential, f.motion, &payload);
  if (f.predictive) {
    ByteWriter w;
    const PredictiveStreams& p = f.predictive_texture;
    w.U8(static_cast<uint8_t>(p.kernel));
    const auto streams = p.Ordered();
    for (const std::vector<uint8_t>* s : streams) w.U32(static_cast<uint32_t>(s->size()));
    for (const std::vector<uint8_t>* s : streams) w.Bytes(*s);
    AppendBox(box::kPredictiveTexture, 0, kBoxFlagEssential, w.bytes(), &payload);
  } else {
    ByteWriter w;
    const BlockParams& p = f.texture.params;
    w.U8(static_cast<uint8_t>(p.kernel));
    w.U8(static_cast<uint8_t>(p.coder));
    w.U8(static_cast<uint8_t>(p.colour));
    w.U8(static_cast<uint8_t>(p.chroma));
    // The version its tools imply (SPEC.md 9.1): 3 with sample-precision, 2
    // with own-band-weights, 1 with texture-precision, else 0. (Every texture
    // of a stream is coded with the same tools, so this is the stream's.)
    const uint8_t version = TextureVersion(
        TextureTools(p.kernel, p.coder, p.colour, p.chroma, p.frac_bits, p.weights, p.sample_frac));
    if (version >= 1) w.U8(p.frac_bits);
    if (version >= 3) w.U8(p.sample_frac);
    for (const ChannelStream& s : f.texture.channels) WriteChannelStream(s, &w);
    AppendBox(box::kTexture, version, kBoxFlagEssential, w.bytes(), &payload);
  }
  if (!f.masks.empty()) {
    ByteWriter w;
    w.U8(static_cast<uint8_t>(f.mask_mode));
    w.Bytes(f.masks);
    AppendBox(box::kMasks, 0, kBoxFlagEssential, w.bytes(), &payload);
  }
  if (!f.vertex_visibility.empty()) {
    AppendBox(box::kVertexVisibility, 0, 0, f.vertex_visibility, &payload);
  }
  ByteWriter crc;
  crc.U32(Crc32c(payload.data(), payload.size()));
  AppendBox(box::kChecksum, 0, kBoxFlagEssential, crc.bytes(), &payload);
  return MakeBox(box::kFragment, 0, kBoxFlagEssential, payload);
}

BoxHeader MotionBoxHeader(const FragmentData& f) {
  BoxHeader h;
  h.type = box::kMotion;
  h.header_size = 12;
  h.size = f.motion.size() + 12;
  return h;
}

namespace {

Status ReadFragmentHeader(const BoxHeader& b, const uint8_t* payload, const FileHeader& h,
                          FragmentInfo* info) {
  const std::string at = BoxContext(b);
  if (b.version != 0) return Unsupported(at + "version " + std::to_string(b.version));
  ByteReader r(payload, b.payload_size());
  info->gop_index = r.U32();
  info->first_frame = r.U32();
  info->frame_count = r.U16();
  info->first_camera = r.U16();
  info->camera_count = r.U16();
  FVV_RETURN_IF_ERROR(CheckFullyRead(r, b));
  const uint64_t span = info->first_frame / h.gop_frames;
  const uint64_t expected_index = span * h.camera_groups() + info->first_camera / h.gop_cameras;
  FVV_RETURN_IF_ERROR(CheckGridCell(h, info->first_frame, info->frame_count, info->first_camera,
                                    info->camera_count, at));
  if (expected_index != info->gop_index) {
    return Corrupt(at + "GOP index " + std::to_string(info->gop_index) + " should be " +
                   std::to_string(expected_index));
  }
  return Status::Ok();
}

Status ReadTexture(const BoxHeader& b, const uint8_t* payload, const FileHeader& h,
                   const FragmentInfo& info, EncodedBlock* texture) {
  const std::string at = BoxContext(b);
  // A version the stream's format version does not have is unknown to it.
  const uint8_t newest = h.format_version >= 7   ? 3
                         : h.format_version >= 6 ? 2
                         : h.format_version >= 3 ? 1
                                                 : 0;
  if (b.version > newest) {
    return Unsupported(at + "version " + std::to_string(b.version) + " (format version " +
                       std::to_string(h.format_version) + " has versions 0.." +
                       std::to_string(newest) + ")");
  }
  // Versions 1 to 3 carry the precision field, versions 2 and 3 weight by own
  // bands, version 3 also says the decoded samples' fractional bits; the
  // header's tool bits say which version every 'texr' of the stream has.
  const uint8_t expected = TextureVersion(h.tools);
  if (b.version != expected) {
    static const char* const kWhy[4] = {
        "declares none of texture-precision, own-band-weights and sample-precision (version 0)",
        "declares texture-precision but not own-band-weights (version 1)",
        "declares own-band-weights but not sample-precision (version 2)",
        "declares sample-precision (version 3)"};
    return Corrupt(at + "version " + std::to_string(b.version) + " in a stream that " +
                   kWhy[expected]);
  }
  ByteReader r(payload, b.payload_size());
  BlockParams& p = texture->params;
  p.kernel = static_cast<WaveletKernel>(r.U8());
  p.coder = static_cast<EntropyCoder>(r.U8());
  p.colour = static_cast<ColourSpace>(r.U8());
  p.chroma = static_cast<ChromaFormat>(r.U8());
  p.frac_bits = b.version >= 1 ? r.U8() : static_cast<uint8_t>(LegacyFracBits(p.kernel));
  p.weights = b.version >= 2 ? BandWeights::kOwnBand : BandWeights::kAxisBands;
  p.sample_frac = b.version >= 3 ? r.U8() : 0;
  p.shape = info.TextureShape(h);
  if (r.overrun()) return Corrupt(at + "too short");
  Status s = ValidateParams(p);
  if (!s.ok()) return Status(s.code(), at + s.message());
  if ((TextureTools(p.kernel, p.coder, p.colour, p.chroma, p.frac_bits, p.weights, p.sample_frac) &
       ~h.tools) != 0) {
    return Corrupt(at + "uses coding tools the file header does not declare");
  }
  static const char* const kNames[3] = {"Y", "U", "V"};
  for (int c = 0; c < 3; ++c) {
    s = ReadChannelStream(&r, kNames[c], &texture->channels[c]);
    if (!s.ok())
      return Status(s.code() == StatusCode::kTruncated ? StatusCode::kCorrupt : s.code(),
                    at + s.message());
  }
  return CheckFullyRead(r, b);
}

// 'ptex' (SPEC.md 9.8): the kernel, every stream's size, the streams.
Status ReadPredictiveTexture(const BoxHeader& b, const uint8_t* payload, const FileHeader& h,
                             const FragmentInfo& info, PredictiveStreams* texture) {
  const std::string at = BoxContext(b);
  if (b.version != 0) return Unsupported(at + "version " + std::to_string(b.version));
  ByteReader r(payload, b.payload_size());
  const uint8_t kernel = r.U8();
  if (r.overrun()) return Corrupt(at + "too short");
  if (kernel > 2) return Corrupt(at + "unknown wavelet kernel " + std::to_string(kernel));
  texture->kernel = static_cast<WaveletKernel>(kernel);
  const uint32_t kernel_tool = kernel == 0 ? kToolHaar : kernel == 1 ? kToolLeGall53 : kToolCdf97;
  if (!(h.tools & kernel_tool)) {
    return Corrupt(at + "uses a kernel the file header does not declare");
  }
  texture->levels = ShapeAdaptiveLevels(h.atlas_width, h.atlas_height);
  // Counts are bounded by the GOP grid (level-checked), sizes by the payload.
  texture->Resize(info.frame_count, info.camera_count);
  const std::vector<std::vector<uint8_t>*> streams = texture->Ordered();
  std::vector<uint32_t> sizes(streams.size());
  uint64_t sum = 0;
  for (uint32_t& size : sizes) {
    size = r.U32();
    sum += size;
  }
  if (r.overrun()) {
    return Corrupt(at + "too short for its " + std::to_string(streams.size()) + " stream sizes");
  }
  if (sum != r.remaining()) {
    return Corrupt(at + "stream sizes add up to " + std::to_string(sum) + " bytes, " +
                   std::to_string(r.remaining()) + " follow");
  }
  for (size_t i = 0; i < streams.size(); ++i) {
    const uint8_t* p = r.Bytes(sizes[i]);
    streams[i]->assign(p, p + sizes[i]);
  }
  return CheckFullyRead(r, b);
}

}  // namespace

Status ReadFragment(const BoxHeader& box, const uint8_t* payload, const FileHeader& h,
                    const FragmentReadOptions& options, FragmentData* f) {
  const std::string at = BoxContext(box);
  if (box.version != 0) return Unsupported(at + "version " + std::to_string(box.version));
  if (box.payload_size() > LimitsOf(h).max_fragment_bytes) {
    return LimitExceeded(at + std::to_string(box.payload_size()) + " bytes (level allows " +
                         std::to_string(LimitsOf(h).max_fragment_bytes) + ")");
  }
  *f = FragmentData();
  // Pass 1: the sub-box structure and the checksum, so damage anywhere is
  // reported as a checksum failure before any payload is interpreted.
  struct SubBox {
    BoxHeader header;
    const uint8_t* payload;
  };
  std::vector<SubBox> subs;
  BoxIterator it(payload, static_cast<size_t>(box.payload_size()), box.offset + box.header_size,
                 "fragment");
  while (!it.done()) {
    SubBox s;
    FVV_RETURN_IF_ERROR(it.Next(&s.header, &s.payload));
    if (subs.size() == 64) return Corrupt(at + "more than 64 sub-boxes");
    subs.push_back(s);
  }
  if (subs.empty() || subs.back().header.type != box::kChecksum) {
    return Corrupt(at + "does not end with an 'fcrc' checksum box");
  }
  {
    const BoxHeader& b = subs.back().header;
    // The checksum box's own header is outside what it covers, so it is fixed.
    if (b.payload_size() != 4 || b.version != 0 || b.flags != kBoxFlagEssential) {
      return Corrupt(BoxContext(b) + "must be version 0, flags 1, 4 bytes of payload");
    }
    ByteReader r(subs.back().payload, 4);
    f->checksum = r.U32();
    const size_t covered = static_cast<size_t>(b.offset - (box.offset + box.header_size));
    if (options.verify_checksum && Crc32c(payload, covered) != f->checksum) {
      return Status(StatusCode::kChecksumMismatch, at + "CRC-32C mismatch (fragment is damaged)");
    }
  }
  subs.pop_back();
  // Pass 2: the payloads.
  bool have_header = false, have_texture = false;
  for (const SubBox& sub : subs) {
    const BoxHeader& b = sub.header;
    const uint8_t* p = sub.payload;
    if (!have_header && b.type != box::kFragmentHeader) {
      return Corrupt(at + "first sub-box is '" + FourCCString(b.type) + "', not 'fghd'");
    }
    const size_t n = static_cast<size_t>(b.payload_size());
    auto once = [&](bool seen) {
      return seen ? Corrupt(BoxContext(b) + "appears twice in one fragment") : Status::Ok();
    };
    if (b.type == box::kFragmentHeader) {
      FVV_RETURN_IF_ERROR(once(have_header));
      FVV_RETURN_IF_ERROR(ReadFragmentHeader(b, p, h, &f->info));
      have_header = true;
    } else if (b.type == box::kMotion) {
      FVV_RETURN_IF_ERROR(once(!f->motion.empty()));
      if (n == 0) return Corrupt(BoxContext(b) + "empty");
      f->motion.assign(p, p + n);
    } else if (b.type == box::kTexture || b.type == box::kPredictiveTexture) {
      const bool predictive = b.type == box::kPredictiveTexture;
      FVV_RETURN_IF_ERROR(once(have_texture));
      if (predictive != ((h.tools & kToolPredictiveTexture) != 0)) {
        return Corrupt(BoxContext(b) + (predictive ? "without" : "with") +
                       " the predictive-texture tool in the header");
      }
      f->predictive = predictive;
      FVV_RETURN_IF_ERROR(predictive
                              ? ReadPredictiveTexture(b, p, h, f->info, &f->predictive_texture)
                              : ReadTexture(b, p, h, f->info, &f->texture));
      have_texture = true;
    } else if (b.type == box::kMasks) {
      FVV_RETURN_IF_ERROR(once(!f->masks.empty()));
      if (n < 2) return Corrupt(BoxContext(b) + "empty");
      const bool known =
          p[0] == static_cast<uint8_t>(MaskCoding::kContext) ||
          (p[0] == static_cast<uint8_t>(MaskCoding::kMixing) && h.format_version >= 2);
      if (!known) {
        return Unsupported(
            BoxContext(b) + "mask mode " + std::to_string(p[0]) +
            (p[0] == static_cast<uint8_t>(MaskCoding::kMixing)
                 ? " needs format version 2, the header says " + std::to_string(h.format_version)
                 : ""));
      }
      f->mask_mode = static_cast<MaskCoding>(p[0]);
      f->masks.assign(p + 1, p + n);
    } else if (b.type == box::kVertexVisibility) {
      FVV_RETURN_IF_ERROR(once(!f->vertex_visibility.empty()));
      if (n == 0) return Corrupt(BoxContext(b) + "empty");
      f->vertex_visibility.assign(p, p + n);
    } else if (b.type == box::kChecksum) {
      return Corrupt(BoxContext(b) + "checksum box before the end of the fragment");
    } else if (b.essential()) {
      return Unsupported(at + "essential sub-box '" + FourCCString(b.type) + "' is unknown");
    }
  }
  if (!have_header) return Corrupt(at + "no 'fghd'");
  if (!have_texture) {
    return Corrupt(at + ((h.tools & kToolPredictiveTexture) ? "no 'ptex'" : "no 'texr'"));
  }
  const bool wants_motion = f->info.first_camera == 0;
  if (wants_motion != !f->motion.empty()) {
    return Corrupt(at + (wants_motion ? "no 'motn' in the first camera group"
                                      : "'motn' outside the first camera group"));
  }
  if (((h.tools & kToolMasks) != 0) != !f->masks.empty()) {
    return Corrupt(at + "'mask' presence disagrees with the header's tools");
  }
  if (!f->vertex_visibility.empty() && !(h.tools & kToolVertexVisibility)) {
    return Corrupt(at + "'vvis' without the vertex-visibility tool in the header");
  }
  return Status::Ok();
}

}  // namespace fvv
