// The box layer of the fvv format (SPEC.md section 2): every syntax structure is a
// box of  size u32 | type 4cc | [largesize u64 when size == 1] | version u8 | flags u24,
// little-endian, so readers can skip what they do not know.
#ifndef FVV_CONTAINER_BOX_H_
#define FVV_CONTAINER_BOX_H_

#include <cstdint>
#include <string>
#include <vector>

#include "codec/base/bit_io.h"
#include "codec/base/status.h"

namespace fvv {

using FourCC = uint32_t;

constexpr FourCC MakeFourCC(const char (&s)[5]) {
  return uint32_t{static_cast<uint8_t>(s[0])} | (uint32_t{static_cast<uint8_t>(s[1])} << 8) |
         (uint32_t{static_cast<uint8_t>(s[2])} << 16) |
         (uint32_t{static_cast<uint8_t>(s[3])} << 24);
}
std::string FourCCString(FourCC type);  // printable, non-ASCII bytes as '?'

// Box types (SPEC.md section 3).
namespace box {
constexpr FourCC kFileHeader = MakeFourCC("fvvh");
constexpr FourCC kCameras = MakeFourCC("cams");
constexpr FourCC kModel = MakeFourCC("modl");
constexpr FourCC kMotionParams = MakeFourCC("mtrk");
constexpr FourCC kMetadata = MakeFourCC("meta");
constexpr FourCC kIndex = MakeFourCC("indx");
constexpr FourCC kFragment = MakeFourCC("frag");
constexpr FourCC kFragmentHeader = MakeFourCC("fghd");
constexpr FourCC kMotion = MakeFourCC("motn");
constexpr FourCC kTexture = MakeFourCC("texr");
constexpr FourCC kPredictiveTexture = MakeFourCC("ptex");
constexpr FourCC kMasks = MakeFourCC("mask");
constexpr FourCC kVertexVisibility = MakeFourCC("vvis");
constexpr FourCC kChecksum = MakeFourCC("fcrc");
constexpr FourCC kTextureHead = MakeFourCC("txhd");    // texture-chunks: the channels' sizes
constexpr FourCC kTextureChunks = MakeFourCC("txck");  // texture-chunks: the chunks, last
constexpr FourCC kSurfaceHead = MakeFourCC("sfhd");    // surface: the values' step and size
}  // namespace box

// flags bit 0: a reader that does not know this box type must stop with
// kUnsupported instead of skipping it.
constexpr uint32_t kBoxFlagEssential = 1;

struct BoxHeader {
  FourCC type = 0;
  uint64_t offset = 0;       // of the box's first byte, in the enclosing unit
  uint64_t size = 0;         // whole box, header included
  uint32_t header_size = 0;  // 12 or 20
  uint8_t version = 0;
  uint32_t flags = 0;

  uint64_t payload_size() const { return size - header_size; }
  // The payload's size once it is held in memory, where it fits size_t (a
  // 32-bit size_t in WebAssembly: readers allocate within the level's limits).
  size_t payload_bytes() const { return static_cast<size_t>(size - header_size); }
  bool essential() const { return (flags & kBoxFlagEssential) != 0; }
};

constexpr uint32_t kMinBoxHeaderSize = 12;
constexpr uint32_t kMaxBoxHeaderSize = 20;

// Parses a box header from `data` (which starts at the box). Truncated when more
// bytes are needed to know the header; Corrupt when size is smaller than the
// header. `where` names the enclosing structure for messages; `offset` is the
// box's position for messages and for BoxHeader::offset.
StatusOr<BoxHeader> ParseBoxHeader(const uint8_t* data, size_t available, uint64_t offset,
                                   const char* where);

// Appends a complete box (a 32-bit size, or the 64-bit escape when needed).
void AppendBox(FourCC type, uint8_t version, uint32_t flags, const std::vector<uint8_t>& payload,
               std::vector<uint8_t>* out);
std::vector<uint8_t> MakeBox(FourCC type, uint8_t version, uint32_t flags,
                             const std::vector<uint8_t>& payload);

// Iterates the boxes inside a payload (nested boxes of a fragment).
class BoxIterator {
 public:
  BoxIterator(const uint8_t* data, size_t size, uint64_t base_offset, const char* where)
      : data_(data), size_(size), base_(base_offset), where_(where) {}
  bool done() const { return pos_ >= size_; }
  // Next box header + payload pointer; Truncated/Corrupt if it does not fit.
  Status Next(BoxHeader* header, const uint8_t** payload);
  size_t position() const { return pos_; }

 private:
  const uint8_t* data_;
  size_t size_;
  uint64_t base_;
  const char* where_;
  size_t pos_ = 0;
};

// "box 'frag' at offset 1234: "
std::string BoxContext(const BoxHeader& h);

// Fails with Corrupt if the reader overran or left bytes unread in a box payload.
Status CheckFullyRead(const ByteReader& r, const BoxHeader& h);

}  // namespace fvv

#endif  // FVV_CONTAINER_BOX_H_
