#include "container/index_box.h"

#include "container/gop_grid.h"

namespace fvv {

uint8_t IndexVersion(uint32_t tools) { return (tools & kToolTextureChunks) ? 1 : 0; }

std::vector<uint8_t> WriteIndexBox(const std::vector<IndexEntry>& entries, uint8_t version) {
  ByteWriter w;
  w.U32(static_cast<uint32_t>(entries.size()));
  for (const IndexEntry& e : entries) {
    w.U32(e.first_frame);
    w.U16(e.frame_count);
    w.U16(e.first_camera);
    w.U16(e.camera_count);
    w.U64(e.offset);
    w.U64(e.size);
    if (version >= 1) w.U32(e.head_size);
  }
  return MakeBox(box::kIndex, version, 0, w.bytes());
}

Status ReadIndex(const BoxHeader& box, const uint8_t* payload, const FileHeader& h,
                 std::vector<IndexEntry>* entries) {
  const std::string at = BoxContext(box);
  if (box.version > 1) return Unsupported(at + "version " + std::to_string(box.version));
  if (box.version != IndexVersion(h.tools)) {
    return Corrupt(at + "version " + std::to_string(box.version) + " in a stream " +
                   (box.version == 0 ? "with" : "without") + " texture-chunks (version " +
                   std::to_string(IndexVersion(h.tools)) + ")");
  }
  const size_t entry_bytes = kIndexEntryBytes + (box.version >= 1 ? 4 : 0);
  ByteReader r(payload, box.payload_bytes());
  const uint32_t count = r.U32();
  if (uint64_t{count} * entry_bytes != r.remaining()) {
    return Corrupt(at + std::to_string(count) + " entries do not fill the " +
                   std::to_string(r.remaining()) + " bytes of the box");
  }
  if (h.frame_count != 0 && uint64_t{count} != uint64_t{h.time_spans()} * h.camera_groups()) {
    return Corrupt(at + std::to_string(count) + " entries, the header's shape needs " +
                   std::to_string(uint64_t{h.time_spans()} * h.camera_groups()));
  }
  if (h.frame_count == 0 && count % h.camera_groups() != 0) {
    return Corrupt(at + std::to_string(count) + " entries end inside a time span of " +
                   std::to_string(h.camera_groups()) + " camera groups");
  }
  entries->assign(count, IndexEntry());
  uint64_t previous_end = 0;
  for (uint32_t i = 0; i < count; ++i) {
    IndexEntry& e = (*entries)[i];
    e.first_frame = r.U32();
    e.frame_count = r.U16();
    e.first_camera = r.U16();
    e.camera_count = r.U16();
    e.offset = r.U64();
    e.size = r.U64();
    if (box.version >= 1) e.head_size = r.U32();
    const std::string en = at + "entry " + std::to_string(i) + ": ";
    if (box.version >= 1 && (e.head_size < kMinBoxHeaderSize || e.head_size > e.size)) {
      return Corrupt(en + "head of " + std::to_string(e.head_size) + " bytes in a fragment of " +
                     std::to_string(e.size));
    }
    FVV_RETURN_IF_ERROR(
        CheckGridCell(h, e.first_frame, e.frame_count, e.first_camera, e.camera_count, en));
    if (i > 0) {
      const IndexEntry& p = (*entries)[i - 1];
      FVV_RETURN_IF_ERROR(
          CheckSpanOrder(h, p.first_frame, p.frame_count, e.first_frame, e.frame_count, en));
    }
    if (e.size < kMinBoxHeaderSize || e.offset < previous_end || e.offset > UINT64_MAX - e.size) {
      return Corrupt(en + "offset " + std::to_string(e.offset) + " size " + std::to_string(e.size) +
                     " overlaps the previous fragment");
    }
    previous_end = e.offset + e.size;
  }
  return Status::Ok();
}

bool IsValidUtf8(const std::string& s) {
  size_t i = 0;
  while (i < s.size()) {
    const uint8_t c = static_cast<uint8_t>(s[i]);
    int extra;
    uint32_t cp;
    if (c < 0x80) {
      ++i;
      continue;
    } else if ((c & 0xE0) == 0xC0) {
      extra = 1;
      cp = c & 0x1F;
    } else if ((c & 0xF0) == 0xE0) {
      extra = 2;
      cp = c & 0x0F;
    } else if ((c & 0xF8) == 0xF0) {
      extra = 3;
      cp = c & 0x07;
    } else {
      return false;
    }
    if (i + extra >= s.size()) return false;
    for (int k = 1; k <= extra; ++k) {
      const uint8_t d = static_cast<uint8_t>(s[i + k]);
      if ((d & 0xC0) != 0x80) return false;
      cp = (cp << 6) | (d & 0x3F);
    }
    static const uint32_t kMin[4] = {0, 0x80, 0x800, 0x10000};
    if (cp < kMin[extra] || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) return false;
    i += extra + 1;
  }
  return true;
}

std::vector<uint8_t> WriteMetadataBox(const Metadata& metadata) {
  ByteWriter w;
  w.U16(static_cast<uint32_t>(metadata.size()));
  for (const auto& kv : metadata) {
    w.Str(kv.first);
    w.Str(kv.second);
  }
  return MakeBox(box::kMetadata, 0, 0, w.bytes());
}

Status ReadMetadata(const BoxHeader& box, const uint8_t* payload, Metadata* metadata) {
  const std::string at = BoxContext(box);
  if (box.version != 0) return Unsupported(at + "version " + std::to_string(box.version));
  ByteReader r(payload, box.payload_bytes());
  const uint32_t count = r.U16();
  if (uint64_t{count} * 4 > r.remaining()) return Corrupt(at + "too short for its entries");
  metadata->clear();
  for (uint32_t i = 0; i < count && !r.overrun(); ++i) {
    std::string key = r.Str(), value = r.Str();
    if (!IsValidUtf8(key) || !IsValidUtf8(value)) {
      return Corrupt(at + "entry " + std::to_string(i) + " is not valid UTF-8");
    }
    metadata->emplace_back(std::move(key), std::move(value));
  }
  return CheckFullyRead(r, box);
}

}  // namespace fvv
