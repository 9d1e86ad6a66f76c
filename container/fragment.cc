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
  if (f.chunked) return uint64_t{f.declared_bytes[0]} + f.declared_bytes[1] + f.declared_bytes[2];
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

std::vector<TextureChunk> PlanTextureChunks(const EncodedBlock& texture) {
  // Each channel's stream in pieces, ranked by what a byte of the piece buys:
  // the slopes of the encoder's RD hulls (which the rate allocation across
  // channels follows too), so that every prefix is near the allocation the
  // encoder would make for its bytes. A stream without a hull (read back from
  // a file) leaves equal shares of the channels, the rule of SPEC.md Annex B.2.
  struct Piece {
    double rank;  // ascending: the steepest slope first
    uint8_t channel;
    uint64_t end;  // the channel's bytes up to the piece's end
  };
  std::vector<Piece> pieces;
  bool hulls = true;
  for (const ChannelStream& s : texture.channels) hulls = hulls && s.rd.size() >= 2;
  for (uint8_t c = 0; c < 3; ++c) {
    const ChannelStream& s = texture.channels[c];
    if (!hulls) {
      for (int k = 1; k <= 64; ++k) pieces.push_back({double(k), c, s.data.size() * k / 64});
      continue;
    }
    uint64_t last = 0;
    for (size_t k = 1; k < s.rd.size(); ++k) {
      const uint64_t end = std::min<uint64_t>(s.rd[k].bytes, s.data.size());
      if (end <= last) continue;
      const double slope =
          (s.rd[k - 1].distortion - s.rd[k].distortion) / double(s.rd[k].bytes - s.rd[k - 1].bytes);
      pieces.push_back({-slope, c, end});
      last = end;
    }
    if (last < s.data.size()) pieces.push_back({0.0, c, s.data.size()});
  }
  std::stable_sort(pieces.begin(), pieces.end(),
                   [](const Piece& a, const Piece& b) { return a.rank < b.rank; });
  // Chunks of about 1/48 of the texture, smaller at first: at most a quarter
  // of the bytes before them (and at least 64), so that a short prefix, which
  // wastes at most its last chunk, still holds every channel's first bytes.
  // A channel's bytes wait until half a chunk has gathered (the hull's first
  // segments are a few bytes each), and go out with any other channel's that
  // reach a quarter of one, so that no channel falls behind the order.
  const uint64_t total = texture.total_bytes();
  const uint64_t largest = std::clamp<uint64_t>((total + 47) / 48, 192, 65535);
  std::array<uint64_t, 3> target{}, written{};
  uint64_t out = 0;
  std::vector<TextureChunk> chunks;
  const auto size_now = [&] { return std::clamp<uint64_t>(out / 4, 64, largest); };
  const auto emit = [&](uint8_t c, uint64_t at_least) {
    while (target[c] - written[c] >= std::max<uint64_t>(at_least, 1)) {
      const uint64_t n = std::min(target[c] - written[c], size_now());
      chunks.push_back({c, static_cast<uint16_t>(n)});
      written[c] += n;
      out += n;
    }
  };
  for (const Piece& p : pieces) {
    target[p.channel] = std::max(target[p.channel], p.end);
    if (target[p.channel] - written[p.channel] < size_now() / 2) continue;
    emit(p.channel, size_now() / 2);
    for (uint8_t c = 0; c < 3; ++c) emit(c, size_now() / 4);
  }
  for (uint8_t c = 0; c < 3; ++c) {
    target[c] = texture.channels[c].data.size();
    emit(c, 1);
  }
  return chunks;
}

namespace {

// The 'texr' fields up to the channel streams (SPEC.md 9.1), shared by 'texr'
// and the chunked texture's head 'txhd'; returns the box version.
uint8_t WriteTextureParams(const BlockParams& p, ByteWriter* w) {
  w->U8(static_cast<uint8_t>(p.kernel));
  w->U8(static_cast<uint8_t>(p.coder));
  w->U8(static_cast<uint8_t>(p.colour));
  w->U8(static_cast<uint8_t>(p.chroma));
  // The version its tools imply (SPEC.md 9.1): 3 with sample-precision, 2
  // with own-band-weights, 1 with texture-precision, else 0. (Every texture
  // of a stream is coded with the same tools, so this is the stream's.)
  const uint8_t version = TextureVersion(
      TextureTools(p.kernel, p.coder, p.colour, p.chroma, p.frac_bits, p.weights, p.sample_frac));
  if (version >= 1) w->U8(p.frac_bits);
  if (version >= 3) w->U8(p.sample_frac);
  return version;
}

// A chunk: channel u8, size u16, crc u32 (CRC-32C of the channel, size and
// data bytes), data.
void AppendChunk(uint8_t channel, const uint8_t* data, uint16_t size, std::vector<uint8_t>* out) {
  uint8_t head[3] = {channel, static_cast<uint8_t>(size & 0xFF), static_cast<uint8_t>(size >> 8)};
  const uint32_t crc = Crc32c(data, size, Crc32c(head, 3));
  out->insert(out->end(), head, head + 3);
  for (int k = 0; k < 4; ++k) out->push_back(static_cast<uint8_t>(crc >> (8 * k)));
  out->insert(out->end(), data, data + size);
}

}  // namespace

std::vector<uint8_t> WriteFragmentBox(const FragmentData& f, bool chunked, uint64_t* head_bytes) {
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
  } else if (!chunked) {
    ByteWriter w;
    const uint8_t version = WriteTextureParams(f.texture.params, &w);
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
  if (f.has_surface) {
    ByteWriter w;
    w.U8(f.surface_head.step_exponent);
    w.U32(f.surface_head.vertex_count);
    w.U32(static_cast<uint32_t>(f.surface.size()));
    AppendBox(box::kSurfaceHead, 0, kBoxFlagEssential, w.bytes(), &payload);
  }
  if (chunked && !f.predictive) {
    // The head's last box before 'fcrc': the texture's parameters and the
    // channels' sizes, so the chunks that follow need no table.
    ByteWriter w;
    const uint8_t version = WriteTextureParams(f.texture.params, &w);
    for (const ChannelStream& s : f.texture.channels) {
      w.U8(s.planes);
      w.U32(static_cast<uint32_t>(s.data.size()));
    }
    AppendBox(box::kTextureHead, version, kBoxFlagEssential, w.bytes(), &payload);
  }
  ByteWriter crc;
  crc.U32(Crc32c(payload.data(), payload.size()));
  AppendBox(box::kChecksum, 0, kBoxFlagEssential, crc.bytes(), &payload);
  if (!chunked || f.predictive) {
    std::vector<uint8_t> out = MakeBox(box::kFragment, 0, kBoxFlagEssential, payload);
    if (head_bytes) *head_bytes = out.size();
    return out;
  }
  std::vector<TextureChunk> chunks = f.chunks;
  if (chunks.empty()) {
    // The surface first: it decodes only whole, and every camera's texture
    // is drawn on it.
    for (size_t at = 0; at < f.surface.size(); at += 65535) {
      chunks.push_back(
          {kSurfaceChannel, static_cast<uint16_t>(std::min<size_t>(65535, f.surface.size() - at))});
    }
    const std::vector<TextureChunk> texture = PlanTextureChunks(f.texture);
    chunks.insert(chunks.end(), texture.begin(), texture.end());
  }
  std::vector<uint8_t> body;
  std::array<size_t, 4> at{};
  for (const TextureChunk& c : chunks) {
    const std::vector<uint8_t>& data =
        c.channel == kSurfaceChannel ? f.surface : f.texture.channels[c.channel].data;
    AppendChunk(c.channel, data.data() + at[c.channel], c.size, &body);
    at[c.channel] += c.size;
  }
  const size_t chunks_at = payload.size();
  AppendBox(box::kTextureChunks, 0, kBoxFlagEssential, body, &payload);
  std::vector<uint8_t> out = MakeBox(box::kFragment, 0, kBoxFlagEssential, payload);
  if (head_bytes) {
    const uint64_t chunks_header = payload.size() - chunks_at - body.size();
    *head_bytes = (out.size() - payload.size()) + chunks_at + chunks_header;
  }
  return out;
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
  ByteReader r(payload, b.payload_bytes());
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

// The 'texr' fields before the channel streams (SPEC.md 9.1), which the
// chunked texture's head 'txhd' shares, version rules included.
Status ReadTextureParams(const BoxHeader& b, const FileHeader& h, const FragmentInfo& info,
                         ByteReader* r, BlockParams* p) {
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
  p->kernel = static_cast<WaveletKernel>(r->U8());
  p->coder = static_cast<EntropyCoder>(r->U8());
  p->colour = static_cast<ColourSpace>(r->U8());
  p->chroma = static_cast<ChromaFormat>(r->U8());
  p->frac_bits = b.version >= 1 ? r->U8() : static_cast<uint8_t>(LegacyFracBits(p->kernel));
  p->weights = b.version >= 2 ? BandWeights::kOwnBand : BandWeights::kAxisBands;
  p->sample_frac = b.version >= 3 ? r->U8() : 0;
  p->shape = info.TextureShape(h);
  if (r->overrun()) return Corrupt(at + "too short");
  Status s = ValidateParams(*p);
  if (!s.ok()) return Status(s.code(), at + s.message());
  if ((TextureTools(p->kernel, p->coder, p->colour, p->chroma, p->frac_bits, p->weights,
                    p->sample_frac) &
       ~h.tools) != 0) {
    return Corrupt(at + "uses coding tools the file header does not declare");
  }
  return Status::Ok();
}

Status ReadTexture(const BoxHeader& b, const uint8_t* payload, const FileHeader& h,
                   const FragmentInfo& info, EncodedBlock* texture) {
  const std::string at = BoxContext(b);
  ByteReader r(payload, b.payload_bytes());
  FVV_RETURN_IF_ERROR(ReadTextureParams(b, h, info, &r, &texture->params));
  static const char* const kNames[3] = {"Y", "U", "V"};
  for (int c = 0; c < 3; ++c) {
    Status s = ReadChannelStream(&r, kNames[c], &texture->channels[c]);
    if (!s.ok())
      return Status(s.code() == StatusCode::kTruncated ? StatusCode::kCorrupt : s.code(),
                    at + s.message());
  }
  return CheckFullyRead(r, b);
}

// 'txhd' (SPEC.md 3.5.1): the 'texr' fields, then per channel its bitplanes
// and its data's size; the data comes in the chunks after 'fcrc'.
Status ReadTextureHead(const BoxHeader& b, const uint8_t* payload, const FileHeader& h,
                       const FragmentInfo& info, FragmentData* f) {
  const std::string at = BoxContext(b);
  ByteReader r(payload, b.payload_bytes());
  FVV_RETURN_IF_ERROR(ReadTextureParams(b, h, info, &r, &f->texture.params));
  static const char* const kNames[3] = {"Y", "U", "V"};
  for (int c = 0; c < 3; ++c) {
    f->texture.channels[c].planes = r.U8();
    f->declared_bytes[c] = r.U32();
    if (r.overrun()) return Corrupt(at + "too short");
    if (f->texture.channels[c].planes > kMaxBitplanes) {
      return Corrupt(at + "channel " + kNames[c] + ": " +
                     std::to_string(f->texture.channels[c].planes) + " bitplanes (at most " +
                     std::to_string(kMaxBitplanes) + ")");
    }
  }
  return CheckFullyRead(r, b);
}

// The chunks of a chunked fragment (SPEC.md 3.5.1), from `data` (the 'txck'
// payload bytes delivered, `whole` when that is all of it): each chunk wholly
// delivered is checked (its CRC first) and appended to its channel; a chunk
// cut by the end of a prefix and what follows are left out.
Status ReadTextureChunks(const BoxHeader& b, const uint8_t* data, uint64_t delivered, bool whole,
                         const FragmentReadOptions& options, FragmentData* f) {
  const std::string at = BoxContext(b);
  uint64_t total = f->has_surface ? f->surface_head.data_size : 0;
  for (uint32_t n : f->declared_bytes) total += n;
  if (total > b.payload_size()) {
    return Corrupt(at + "the head declares " + std::to_string(total) + " bytes of chunks, " +
                   std::to_string(b.payload_size()) + " follow");
  }
  f->surface.clear();
  f->surface.reserve(f->has_surface ? f->surface_head.data_size : 0);
  for (int c = 0; c < 3; ++c) {
    f->texture.channels[c].data.clear();
    f->texture.channels[c].data.reserve(f->declared_bytes[c]);
  }
  uint64_t pos = 0;
  while (pos + kChunkHeaderBytes <= delivered) {
    const uint8_t* p = data + pos;
    const uint8_t channel = p[0];
    const uint16_t size = static_cast<uint16_t>(p[1] | (p[2] << 8));
    if (pos + kChunkHeaderBytes + size > delivered) break;  // cut by the prefix
    const std::string where = at + "chunk at payload byte " + std::to_string(pos) + ": ";
    const uint32_t crc =
        uint32_t{p[3]} | (uint32_t{p[4]} << 8) | (uint32_t{p[5]} << 16) | (uint32_t{p[6]} << 24);
    if (options.verify_checksum && Crc32c(p + kChunkHeaderBytes, size, Crc32c(p, 3)) != crc) {
      return Status(StatusCode::kChecksumMismatch, where + "CRC-32C mismatch (chunk is damaged)");
    }
    if (channel > kSurfaceChannel || (channel == kSurfaceChannel && !f->has_surface)) {
      return Corrupt(where + "channel " + std::to_string(channel) +
                     (channel == kSurfaceChannel ? " (the surface) without 'sfhd'" : ""));
    }
    if (size == 0) return Corrupt(where + "empty");
    const bool surface = channel == kSurfaceChannel;
    std::vector<uint8_t>& out = surface ? f->surface : f->texture.channels[channel].data;
    const uint32_t declared = surface ? f->surface_head.data_size : f->declared_bytes[channel];
    if (out.size() + size > declared) {
      return Corrupt(where + "channel " + std::to_string(channel) + " runs past the " +
                     std::to_string(declared) + " bytes its head declares");
    }
    out.insert(out.end(), p + kChunkHeaderBytes, p + kChunkHeaderBytes + size);
    f->chunks.push_back({channel, size});
    pos += kChunkHeaderBytes + size;
  }
  if (!whole) return Status::Ok();
  if (pos != delivered) {
    return Corrupt(at + "a chunk runs past the end of the fragment at payload byte " +
                   std::to_string(pos));
  }
  for (int c = 0; c < 3; ++c) {
    if (f->texture.channels[c].data.size() != f->declared_bytes[c]) {
      return Corrupt(at + "channel " + std::to_string(c) + "'s chunks hold " +
                     std::to_string(f->texture.channels[c].data.size()) + " bytes, its head " +
                     "declares " + std::to_string(f->declared_bytes[c]));
    }
  }
  if (f->has_surface && f->surface.size() != f->surface_head.data_size) {
    return Corrupt(at + "the surface's chunks hold " + std::to_string(f->surface.size()) +
                   " bytes, 'sfhd' declares " + std::to_string(f->surface_head.data_size));
  }
  return Status::Ok();
}

// 'sfhd' (SPEC.md 3.5.2): the values' step, the model's vertex count and the
// coded values' size.
Status ReadSurfaceHead(const BoxHeader& b, const uint8_t* payload, SurfaceHead* head) {
  const std::string at = BoxContext(b);
  if (b.version != 0) return Unsupported(at + "version " + std::to_string(b.version));
  ByteReader r(payload, b.payload_bytes());
  head->step_exponent = r.U8();
  head->vertex_count = r.U32();
  head->data_size = r.U32();
  FVV_RETURN_IF_ERROR(CheckFullyRead(r, b));
  if (head->step_exponent < kMinSurfaceStepExponent ||
      head->step_exponent > kMaxSurfaceStepExponent) {
    return Corrupt(at + "step exponent " + std::to_string(head->step_exponent) + " (" +
                   std::to_string(kMinSurfaceStepExponent) + ".." +
                   std::to_string(kMaxSurfaceStepExponent) + ")");
  }
  if (head->data_size == 0) return Corrupt(at + "no coded values");
  return Status::Ok();
}

// 'ptex' (SPEC.md 9.8): the kernel, every stream's size, the streams.
Status ReadPredictiveTexture(const BoxHeader& b, const uint8_t* payload, const FileHeader& h,
                             const FragmentInfo& info, PredictiveStreams* texture) {
  const std::string at = BoxContext(b);
  if (b.version != 0) return Unsupported(at + "version " + std::to_string(b.version));
  ByteReader r(payload, b.payload_bytes());
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
  if (options.max_fragment_bytes != 0 && box.payload_size() > options.max_fragment_bytes) {
    return LimitExceeded(at + std::to_string(box.payload_size()) + " bytes (this decoder holds " +
                         std::to_string(options.max_fragment_bytes) + ")");
  }
  *f = FragmentData();
  const bool chunked = (h.tools & kToolTextureChunks) != 0;
  f->chunked = chunked;
  const uint64_t payload_size = box.payload_size();
  uint64_t available = payload_size;  // payload bytes delivered
  if (options.delivered != 0 && options.delivered < box.size) {
    if (!chunked || options.delivered < box.header_size) {
      return Truncated(at + "only the first " + std::to_string(options.delivered) + " of its " +
                       std::to_string(box.size) + " bytes" +
                       (chunked ? "" : " (a prefix decodes only with texture-chunks)"));
    }
    available = options.delivered - box.header_size;
  }
  // Pass 1: the sub-box structure and the checksum, so damage anywhere is
  // reported as a checksum failure before any payload is interpreted. A
  // chunked fragment's head ends with the header of 'txck', whose chunks
  // follow to the end of the fragment (SPEC.md 3.5.1).
  struct SubBox {
    BoxHeader header;
    const uint8_t* payload;
  };
  std::vector<SubBox> subs;
  BoxHeader chunks_box;
  bool have_chunks = false;
  const uint64_t base = box.offset + box.header_size;
  const auto head_cut = [&] {
    return Truncated(at + "the prefix of " + std::to_string(options.delivered) +
                     " bytes ends inside the fragment's head");
  };
  for (uint64_t pos = 0; pos < payload_size;) {
    if (pos >= available) return head_cut();
    StatusOr<BoxHeader> parsed =
        ParseBoxHeader(payload + pos, static_cast<size_t>(available - pos), base + pos, "fragment");
    if (!parsed.ok() && parsed.status().code() == StatusCode::kTruncated &&
        available < payload_size) {
      return head_cut();
    }
    FVV_RETURN_IF_ERROR(parsed.status());
    const BoxHeader b = *parsed;
    if (b.size > payload_size - pos) {
      return Corrupt("fragment: " + BoxContext(b) + "size " + std::to_string(b.size) +
                     " runs past the end of its parent (" + std::to_string(payload_size - pos) +
                     " bytes left)");
    }
    if (subs.size() == 64) return Corrupt(at + "more than 64 sub-boxes");
    if (chunked && b.type == box::kTextureChunks) {
      if (pos + b.size != payload_size) {
        return Corrupt(BoxContext(b) + "must be the fragment's last sub-box");
      }
      if (b.version != 0)
        return Unsupported(BoxContext(b) + "version " + std::to_string(b.version));
      chunks_box = b;
      have_chunks = true;
      f->head_bytes = box.header_size + pos + b.header_size;
      break;
    }
    if (b.size > available - pos) return head_cut();
    subs.push_back({b, payload + pos + b.header_size});
    pos += b.size;
  }
  if (subs.empty() || subs.back().header.type != box::kChecksum) {
    return Corrupt(at + (chunked ? "does not have an 'fcrc' checksum box just before 'txck'"
                                 : "does not end with an 'fcrc' checksum box"));
  }
  if (chunked && !have_chunks) return Corrupt(at + "no 'txck' after its 'fcrc'");
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
    } else if (b.type == box::kTextureHead) {
      FVV_RETURN_IF_ERROR(once(have_texture));
      if (!chunked) return Corrupt(BoxContext(b) + "without the texture-chunks tool in the header");
      FVV_RETURN_IF_ERROR(ReadTextureHead(b, p, h, f->info, f));
      have_texture = true;
    } else if (b.type == box::kTexture || b.type == box::kPredictiveTexture) {
      const bool predictive = b.type == box::kPredictiveTexture;
      FVV_RETURN_IF_ERROR(once(have_texture));
      if (chunked) {
        return Corrupt(BoxContext(b) + "in a stream with texture-chunks (its texture is 'txhd')");
      }
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
    } else if (b.type == box::kSurfaceHead) {
      FVV_RETURN_IF_ERROR(once(f->has_surface));
      if (!(h.tools & kToolSurface)) {
        return Corrupt(BoxContext(b) + "without the surface tool in the header");
      }
      FVV_RETURN_IF_ERROR(ReadSurfaceHead(b, p, &f->surface_head));
      f->has_surface = true;
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
    return Corrupt(at + (chunked                              ? "no 'txhd'"
                         : (h.tools & kToolPredictiveTexture) ? "no 'ptex'"
                                                              : "no 'texr'"));
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
  if (f->has_surface && !wants_motion) {
    return Corrupt(at + "'sfhd' outside the first camera group");
  }
  if (!chunked) return Status::Ok();
  const uint64_t chunks_at = chunks_box.offset - base + chunks_box.header_size;
  return ReadTextureChunks(chunks_box, payload + chunks_at, available - chunks_at,
                           available == payload_size, options, f);
}

namespace {

// Each channel's bytes (Y, U, V, surface) in the chunks that lie wholly
// within the box's first `prefix` bytes (0: all).
std::array<uint64_t, 4> DeliveredChunkBytes(const FragmentData& f, uint64_t prefix) {
  std::array<uint64_t, 4> bytes{};
  uint64_t end = f.head_bytes;
  for (const TextureChunk& c : f.chunks) {
    end += kChunkHeaderBytes + c.size;
    if (prefix != 0 && end > prefix) break;
    bytes[std::min<uint8_t>(c.channel, kSurfaceChannel)] += c.size;
  }
  return bytes;
}

}  // namespace

StatusOr<std::array<uint64_t, 3>> ChunkedPrefixBytes(const FragmentData& f, uint64_t prefix) {
  if (prefix != 0 && prefix < f.head_bytes) {
    return Truncated("fragment " + std::to_string(f.info.gop_index) + ": a prefix of " +
                     std::to_string(prefix) + " bytes ends inside its head of " +
                     std::to_string(f.head_bytes));
  }
  const std::array<uint64_t, 4> bytes = DeliveredChunkBytes(f, prefix);
  return std::array<uint64_t, 3>{bytes[0], bytes[1], bytes[2]};
}

uint64_t SurfaceChunkBytes(const FragmentData& f) {
  if (!f.has_surface) return 0;
  const uint64_t data = f.surface_head.data_size;
  uint64_t seen = 0, bytes = 0;
  for (const TextureChunk& c : f.chunks) {
    if (c.channel != kSurfaceChannel) continue;
    seen += c.size;
    bytes += kChunkHeaderBytes + c.size;
  }
  if (seen == data) return bytes;
  return data + (data + 65534) / 65535 * kChunkHeaderBytes;
}

bool PrefixHoldsSurface(const FragmentData& f, uint64_t prefix) {
  return f.has_surface &&
         DeliveredChunkBytes(f, prefix)[kSurfaceChannel] == f.surface_head.data_size;
}

}  // namespace fvv
