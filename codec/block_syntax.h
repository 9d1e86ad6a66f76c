// Serialisation of a coded block: the payload syntax shared by the stand-alone
// block file (`fvv block`, docs/block_file.md) and the container's texture
// fragments (SPEC.md 9.1). In memory only; the caller does file I/O.
//
//   block_file()       magic "fvvb", version u8 (1..7), block_params(), channel_stream() x 3
//   block_params()     kernel u8, coder u8, colour u8, chroma u8, [version 2: frac_bits u8],
//                      [version 6: sample_frac u8],
//                      frames u32, cameras u32, height u32, width u32
//                      (version 1: frac_bits is 2 for the 9/7, 0 otherwise; the
//                      version also sets the coders allowed and the band weights)
//   channel_stream()   planes u8, point_count u16, point_count x (bytes u32, plane u8,
//                      pass u8), data_size u32, data_size bytes
// Integers are little-endian.
#ifndef FVV_CODEC_BLOCK_SYNTAX_H_
#define FVV_CODEC_BLOCK_SYNTAX_H_

#include <cstdint>
#include <vector>

#include "codec/base/bit_io.h"
#include "codec/base/status.h"
#include "codec/block_codec.h"

namespace fvv {

// Version 2 adds the 9/7's sample precision; writers use version 1 for blocks
// that version 1 can describe.
// Version 3 admits coder 2 (arith2), version 4 coder 3 (arith3). Version 5
// weights coefficients by their own band (BandWeights::kOwnBand); versions 1 to
// 4 by the per-axis bands of their position. Version 6 says the decoded
// samples' fractional bits (BlockParams::sample_frac). Version 7 admits coder 4
// (arith4, the quadtree).
constexpr uint8_t kBlockFileVersion = 7;

// The block file version that can hold these parameters.
uint8_t BlockFileVersionFor(const BlockParams& p);
void WriteBlockParams(const BlockParams& p, uint8_t version, ByteWriter* w);
Status ReadBlockParams(ByteReader* r, uint8_t version, BlockParams* p);
void WriteChannelStream(const ChannelStream& s, ByteWriter* w);
Status ReadChannelStream(ByteReader* r, const char* name, ChannelStream* s);

std::vector<uint8_t> WriteBlockFile(const EncodedBlock& block);
StatusOr<EncodedBlock> ReadBlockFile(const uint8_t* data, size_t size);

}  // namespace fvv

#endif  // FVV_CODEC_BLOCK_SYNTAX_H_
