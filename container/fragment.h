// The fragment box 'frag' (SPEC.md 3.5): one GOP (a time span x a camera range),
// decodable on its own. Sub-boxes: 'fghd' (first), 'motn' (in the fragment of
// camera range 0), 'texr' (or 'ptex' with the predictive-texture tool),
// 'mask' and 'vvis' when the header declares those tools, and 'fcrc' (last):
// CRC-32C of every payload byte before it.
#ifndef FVV_CONTAINER_FRAGMENT_H_
#define FVV_CONTAINER_FRAGMENT_H_

#include <cstdint>
#include <vector>

#include "codec/base/status.h"
#include "codec/block_codec.h"
#include "codec/mask.h"
#include "codec/predictive_texture.h"
#include "container/box.h"
#include "container/file_header.h"

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
};

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

// Texture bytes of a fragment (whichever texture box it has).
uint64_t TextureBytes(const FragmentData& f);

// The fragment info the header's GOP grid gives to fragment `gop_index`.
StatusOr<FragmentInfo> FragmentInfoFor(const FileHeader& h, uint32_t gop_index);

std::vector<uint8_t> WriteFragmentBox(const FragmentData& f);

struct FragmentReadOptions {
  bool verify_checksum = true;
};
// Parses a 'frag' payload, checking it against the header (GOP grid, declared
// tools, level limits) and its checksum.
Status ReadFragment(const BoxHeader& box, const uint8_t* payload, const FileHeader& h,
                    const FragmentReadOptions& options, FragmentData* f);

// Motion 'motn' sub-box header of a parsed fragment (for DecodeMotion).
BoxHeader MotionBoxHeader(const FragmentData& f);

}  // namespace fvv

#endif  // FVV_CONTAINER_FRAGMENT_H_
