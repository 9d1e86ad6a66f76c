#include "codec/block_syntax.h"

#include <cstring>
#include <string>

namespace fvv {
namespace {
constexpr char kMagic[4] = {'f', 'v', 'v', 'b'};
constexpr uint32_t kMaxPoints = 2 * kMaxBitplanes;
}  // namespace

uint8_t BlockFileVersionFor(const BlockParams& p) {
  if (p.coder == EntropyCoder::kQuadtree) return 7;
  if (p.sample_frac > 0) return 6;
  if (p.weights == BandWeights::kOwnBand) return 5;
  if (p.coder == EntropyCoder::kSetSignContexts) return 4;
  if (p.coder == EntropyCoder::kNeighbourContexts) return 3;
  return p.frac_bits == LegacyFracBits(p.kernel) ? 1 : 2;
}

void WriteBlockParams(const BlockParams& p, uint8_t version, ByteWriter* w) {
  w->U8(static_cast<uint8_t>(p.kernel));
  w->U8(static_cast<uint8_t>(p.coder));
  w->U8(static_cast<uint8_t>(p.colour));
  w->U8(static_cast<uint8_t>(p.chroma));
  if (version >= 2) w->U8(p.frac_bits);
  if (version >= 6) w->U8(p.sample_frac);
  for (int a = 0; a < kAxes; ++a) w->U32(p.shape.n[a]);
}

Status ReadBlockParams(ByteReader* r, uint8_t version, BlockParams* p) {
  p->kernel = static_cast<WaveletKernel>(r->U8());
  p->coder = static_cast<EntropyCoder>(r->U8());
  p->colour = static_cast<ColourSpace>(r->U8());
  p->chroma = static_cast<ChromaFormat>(r->U8());
  p->frac_bits = version >= 2 ? r->U8() : static_cast<uint8_t>(LegacyFracBits(p->kernel));
  p->weights = version >= 5 ? BandWeights::kOwnBand : BandWeights::kAxisBands;
  p->sample_frac = version >= 6 ? r->U8() : 0;
  for (int a = 0; a < kAxes; ++a) p->shape.n[a] = r->U32();
  if (r->overrun()) return Truncated("block parameters end early");
  // Each coder's first block file version: coder 2 in 3, coder 3 in 4, coder 4 in 7.
  const int coder = static_cast<int>(p->coder);
  const int first = coder == 4 ? 7 : coder + 1;
  if (coder >= 2 && coder < kEntropyCoders && version < first)
    return Corrupt("entropy coder " + std::to_string(coder) + " (" + CoderName(p->coder) +
                   ") in a version " + std::to_string(version) + " block file (it needs version " +
                   std::to_string(first) + ")");
  return ValidateParams(*p);
}

void WriteChannelStream(const ChannelStream& s, ByteWriter* w) {
  w->U8(s.planes);
  w->U16(static_cast<uint32_t>(s.points.size()));
  for (const TruncationPoint& t : s.points) {
    w->U32(t.bytes);
    w->U8(t.plane);
    w->U8(t.pass);
  }
  w->U32(static_cast<uint32_t>(s.data.size()));
  w->Bytes(s.data.data(), s.data.size());
}

Status ReadChannelStream(ByteReader* r, const char* name, ChannelStream* s) {
  const std::string where = std::string("channel ") + name;
  s->planes = r->U8();
  const uint32_t count = r->U16();
  if (r->overrun()) return Truncated(where + ": stream header ends early");
  if (s->planes > kMaxBitplanes)
    return Corrupt(where + ": " + std::to_string(s->planes) + " bitplanes (at most " +
                   std::to_string(kMaxBitplanes) + ")");
  if (count > kMaxPoints)
    return LimitExceeded(where + ": " + std::to_string(count) + " truncation points (at most " +
                         std::to_string(kMaxPoints) + ")");
  s->points.resize(count);
  for (TruncationPoint& t : s->points) {
    t.bytes = r->U32();
    t.plane = r->U8();
    t.pass = r->U8();
  }
  const uint32_t size = r->U32();
  if (r->overrun()) return Truncated(where + ": truncation table ends early");
  if (size > r->remaining())
    return Truncated(where + ": declares " + std::to_string(size) + " bytes, " +
                     std::to_string(r->remaining()) + " remain");
  const uint8_t* data = r->Bytes(size);
  s->data.assign(data, data + size);
  for (uint32_t i = 0; i < count; ++i) {
    const TruncationPoint& t = s->points[i];
    if (t.bytes > size || t.pass > 1 || t.plane >= s->planes ||
        (i > 0 && t.bytes < s->points[i - 1].bytes))
      return Corrupt(where + ": truncation point " + std::to_string(i) + " is inconsistent");
  }
  return Status::Ok();
}

std::vector<uint8_t> WriteBlockFile(const EncodedBlock& block) {
  ByteWriter w;
  for (char c : kMagic) w.U8(static_cast<uint8_t>(c));
  const uint8_t version = BlockFileVersionFor(block.params);
  w.U8(version);
  WriteBlockParams(block.params, version, &w);
  for (const ChannelStream& s : block.channels) WriteChannelStream(s, &w);
  return std::move(w.bytes());
}

StatusOr<EncodedBlock> ReadBlockFile(const uint8_t* data, size_t size) {
  if (size < 4)
    return Truncated("block file of " + std::to_string(size) + " bytes ends in its magic");
  ByteReader r(data, size);
  const uint8_t* magic = r.Bytes(4);
  if (!magic || std::memcmp(magic, kMagic, 4) != 0)
    return Corrupt("not an fvv block file (magic 'fvvb' missing)");
  const uint8_t version = r.U8();
  if (r.overrun()) return Truncated("block file ends in its header");
  if (version < 1 || version > kBlockFileVersion)
    return Unsupported("block file version " + std::to_string(version) +
                       " (this decoder reads 1.." + std::to_string(kBlockFileVersion) + ")");
  EncodedBlock block;
  FVV_RETURN_IF_ERROR(ReadBlockParams(&r, version, &block.params));
  static const char* const kNames[3] = {"Y", "U", "V"};
  for (int c = 0; c < 3; ++c)
    FVV_RETURN_IF_ERROR(ReadChannelStream(&r, kNames[c], &block.channels[c]));
  if (r.remaining() != 0)
    return Corrupt(std::to_string(r.remaining()) + " unexpected bytes after the last channel");
  return block;
}

}  // namespace fvv
