// The fragment box 'frag' (SPEC.md 3.5): one GOP (a time span x a camera range),
// decodable on its own. Sub-boxes: 'fghd' (first), 'motn' (in the fragment of
// camera range 0), 'texr' (or 'ptex' with the predictive-texture tool),
// 'mask' and 'vvis' when the header declares those tools, and 'fcrc' (last):
// CRC-32C of every payload byte before it. With texture-chunks (SPEC.md 3.5.1)
// the texture is a head 'txhd' before 'fcrc' and the chunks' box 'txck' after
// it, so that every prefix of the box past its head decodes.
#ifndef FVV_CONTAINER_FRAGMENT_H_
#define FVV_CONTAINER_FRAGMENT_H_

#include <array>
#include <cstdint>
#include <vector>

#include "codec/base/status.h"
#include "codec/block_codec.h"
#include "codec/mask.h"
#include "codec/predictive_texture.h"
#include "container/box.h"
#include "container/file_header.h"
#include "container/surface_displacement.h"

namespace fvv {

struct FragmentInfo {
  uint32_t gop_index = 0;  // time_span * camera_groups + camera_group
  uint32_t first_frame = 0;
  uint16_t frame_count = 0;
  uint16_t first_camera = 0;
  uint16_t camera_count = 0;

  Shape4D TextureShape(const FileHeader& h) const {
    Shape4D s;
    s.n = {frame_count, camera_count, h.atlas_height, h.atlas_width};
    return s;
  }
};

// One chunk of a chunked texture (SPEC.md 3.5.1): the next `size` bytes of
// channel `channel` (0 Y, 1 U, 2 V; 3 the surface of 3.5.2).
struct TextureChunk {
  uint8_t channel = 0;
  uint16_t size = 0;
};
// Bytes of a chunk before its data: channel u8, size u16, crc u32.
constexpr uint32_t kChunkHeaderBytes = 7;
constexpr uint8_t kSurfaceChannel = 3;

// A fragment's coded payloads, as the writer takes them and the reader returns
// them (decoding the payloads is the decoder's job).
struct FragmentData {
  FragmentInfo info;
  std::vector<uint8_t> motion;                  // 'motn' payload; empty = absent
  EncodedBlock texture;                         // params.shape follows info and the header
  bool predictive = false;                      // the texture is 'ptex', in `predictive_texture`
  PredictiveStreams predictive_texture;         // levels follow the atlas size
  std::vector<uint8_t> masks;                   // coded masks (codec/mask.h); empty = absent
  MaskCoding mask_mode = MaskCoding::kContext;  // how `masks` is coded (mode 2: version 2)
  std::vector<uint8_t> vertex_visibility;       // coded; empty = absent
  uint32_t checksum = 0;                        // filled by the reader

  // Texture in chunks (tool bit 21, SPEC.md 3.5.1), as the reader found it
  // (the writer follows the header's tools). The reader fills the rest: `texture` holds the chunks
  // it was given whole, `chunks` lists them in stream order, `declared_bytes` are the channels'
  // whole sizes and `head_bytes` the box's bytes before the first chunk. For the writer, `chunks`
  // is the order to write (empty: its own).
  bool chunked = false;
  std::vector<TextureChunk> chunks;
  std::array<uint32_t, 3> declared_bytes{};
  uint64_t head_bytes = 0;

  // The surface of the fragment's frames (tool bit 22, SPEC.md 3.5.2), in the
  // first camera group's fragment: its head 'sfhd' and its coded values
  // (surface_displacement.h), which travel in chunks of channel 3. The reader
  // leaves `surface` shorter than surface_head.data_size when a prefix ends
  // before its last chunk.
  bool has_surface = false;
  SurfaceHead surface_head;
  std::vector<uint8_t> surface;
};

// Whether a prefix of `prefix` bytes of a chunked fragment (0: all) holds the
// whole surface (SPEC.md 3.5.2: the surface decodes only whole).
bool PrefixHoldsSurface(const FragmentData& f, uint64_t prefix);

// The bytes past the head that carry the surface whole, chunk headers
// included: as the fragment's chunks give them where it was read that far,
// else the least any writer needs (chunks of at most 65535 bytes). 0 without
// a surface. What a player fetching over HTTP must add to a fragment's head
// for its surface to decode.
uint64_t SurfaceChunkBytes(const FragmentData& f);

// The chunk order the writer uses when FragmentData::chunks is empty: the
// channels interleaved in the order of the encoder's RD hulls (ChannelStream::
// rd), steepest first, so that every prefix is near the allocation the encoder
// would make for its bytes; equal shares of the channels without hulls. Chunks
// of about 2 % of the texture (a prefix wastes at most one).
std::vector<TextureChunk> PlanTextureChunks(const EncodedBlock& texture);

// Of a chunked fragment read whole: each channel's bytes in the chunks that lie
// wholly within the box's first `prefix` bytes (0, or the box's size or more:
// all). Truncated when the prefix ends inside the head (SPEC.md 3.5.1).
StatusOr<std::array<uint64_t, 3>> ChunkedPrefixBytes(const FragmentData& f, uint64_t prefix);

// The coding tools (FileHeader::tools bits) a texture coded with these
// parameters uses; the header must declare all of them. frac_bits is
// BlockParams::frac_bits: a 9/7 precision other than 2 needs texture-precision;
// own-band weights need own-band-weights; fractional output samples
// (sample_frac > 0) need sample-precision, which extends own-band-weights.
uint32_t TextureTools(WaveletKernel kernel, EntropyCoder coder, ColourSpace colour,
                      ChromaFormat chroma, int frac_bits, BandWeights weights, int sample_frac = 0);
// The 'texr' version of a stream with these tools (SPEC.md 9.1).
uint8_t TextureVersion(uint32_t tools);

// The format version a stream needs: that of its tools, and 2 for mask mode 2.
uint16_t RequiredFormatVersion(uint32_t tools, MaskCoding mask_coding);

// Texture bytes of a fragment (whichever texture box it has; with chunks, all
// its head declares, also where only a prefix was read).
uint64_t TextureBytes(const FragmentData& f);

// The fragment info the header's GOP grid gives to fragment `gop_index`.
StatusOr<FragmentInfo> FragmentInfoFor(const FileHeader& h, uint32_t gop_index);

// `chunked`: the texture in 'txhd' and chunks (the header's texture-chunks
// tool), else in 'texr'. `head_bytes` (optional) receives the box's bytes
// before its first chunk (the whole box when not chunked).
std::vector<uint8_t> WriteFragmentBox(const FragmentData& f, bool chunked,
                                      uint64_t* head_bytes = nullptr);

struct FragmentReadOptions {
  bool verify_checksum = true;
  // Bytes of the box delivered, from its first byte (a prefix fetched over the
  // network); 0 = all. Only a chunked fragment decodes from a prefix: any
  // other shorter than its box is Truncated, and so is a prefix that ends
  // inside a chunked fragment's head.
  uint64_t delivered = 0;
  // The decoder's claim (SPEC.md 5.1), which the readers hold a stream to:
  // fragments of more payload bytes are LimitExceeded before they are
  // buffered or read, and so is a header whose GOPs hold more samples; 0 =
  // the level's limit.
  uint64_t max_fragment_bytes = 0;
  uint64_t max_gop_samples = 0;
};
// Parses a 'frag' payload, checking it against the header (GOP grid, declared
// tools, level limits) and its checksums. `payload` holds the box's payload,
// or with options.delivered, that many bytes of the box less its header.
Status ReadFragment(const BoxHeader& box, const uint8_t* payload, const FileHeader& h,
                    const FragmentReadOptions& options, FragmentData* f);

// Motion 'motn' sub-box header of a parsed fragment (for DecodeMotion).
BoxHeader MotionBoxHeader(const FragmentData& f);

}  // namespace fvv

#endif  // FVV_CONTAINER_FRAGMENT_H_
