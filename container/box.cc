#include "container/box.h"

namespace fvv {

std::string FourCCString(FourCC type) {
  std::string s(4, '?');
  for (int i = 0; i < 4; ++i) {
    const char c = static_cast<char>((type >> (8 * i)) & 0xFF);
    if (c >= 0x20 && c < 0x7F) s[i] = c;
  }
  return s;
}

std::string BoxContext(const BoxHeader& h) {
  return "box '" + FourCCString(h.type) + "' at offset " + std::to_string(h.offset) + ": ";
}

StatusOr<BoxHeader> ParseBoxHeader(const uint8_t* data, size_t available, uint64_t offset,
                                   const char* where) {
  const std::string at = std::string(where) + ", offset " + std::to_string(offset) + ": ";
  if (available < 8)
    return Truncated(at + "box header needs 8 bytes, " + std::to_string(available) + " left");
  ByteReader r(data, available);
  BoxHeader h;
  h.offset = offset;
  const uint32_t size32 = r.U32();
  h.type = r.U32();
  if (size32 == 1) {
    if (available < 16) return Truncated(at + "64-bit box size cut off");
    h.size = r.U64();
    h.header_size = 20;
  } else {
    h.size = size32;
    h.header_size = 12;
  }
  if (size32 == 0) {
    return Corrupt(at + "box '" + FourCCString(h.type) + "' has size 0 (not allowed in fvv)");
  }
  if (h.size < h.header_size) {
    return Corrupt(at + "box '" + FourCCString(h.type) + "' size " + std::to_string(h.size) +
                   " is smaller than its header (" + std::to_string(h.header_size) + ")");
  }
  if (available < h.header_size) return Truncated(at + "box header cut off");
  h.version = r.U8();
  h.flags = r.U8();
  h.flags |= uint32_t{r.U8()} << 8;
  h.flags |= uint32_t{r.U8()} << 16;
  return h;
}

void AppendBox(FourCC type, uint8_t version, uint32_t flags, const std::vector<uint8_t>& payload,
               std::vector<uint8_t>* out) {
  ByteWriter w;
  const uint64_t small = uint64_t{payload.size()} + 12;
  if (small <= 0xFFFFFFFFu) {
    w.U32(static_cast<uint32_t>(small));
    w.U32(type);
  } else {
    w.U32(1);
    w.U32(type);
    w.U64(uint64_t{payload.size()} + 20);
  }
  w.U8(version);
  w.U8(flags);
  w.U8(flags >> 8);
  w.U8(flags >> 16);
  out->insert(out->end(), w.bytes().begin(), w.bytes().end());
  out->insert(out->end(), payload.begin(), payload.end());
}

std::vector<uint8_t> MakeBox(FourCC type, uint8_t version, uint32_t flags,
                             const std::vector<uint8_t>& payload) {
  std::vector<uint8_t> out;
  out.reserve(payload.size() + 12);
  AppendBox(type, version, flags, payload, &out);
  return out;
}

Status BoxIterator::Next(BoxHeader* header, const uint8_t** payload) {
  FVV_ASSIGN_OR_RETURN(*header, ParseBoxHeader(data_ + pos_, size_ - pos_, base_ + pos_, where_));
  if (header->size > size_ - pos_) {
    return Corrupt(std::string(where_) + ": " + BoxContext(*header) + "size " +
                   std::to_string(header->size) + " runs past the end of its parent (" +
                   std::to_string(size_ - pos_) + " bytes left)");
  }
  *payload = data_ + pos_ + header->header_size;
  pos_ += static_cast<size_t>(header->size);
  return Status::Ok();
}

Status CheckFullyRead(const ByteReader& r, const BoxHeader& h) {
  if (r.overrun()) return Corrupt(BoxContext(h) + "payload ends inside a field");
  if (r.remaining() != 0) {
    return Corrupt(BoxContext(h) + std::to_string(r.remaining()) +
                   " unexpected bytes after the last field");
  }
  return Status::Ok();
}

}  // namespace fvv
