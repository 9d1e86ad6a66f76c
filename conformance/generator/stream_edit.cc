#include "conformance/generator/stream_edit.h"

#include <functional>

#include "container/crc32c.h"

namespace fvv {

StatusOr<std::vector<EditBox>> SplitBoxes(const std::vector<uint8_t>& bytes) {
  std::vector<EditBox> boxes;
  uint64_t pos = 0;
  while (pos < bytes.size()) {
    FVV_ASSIGN_OR_RETURN(const BoxHeader h,
                         ParseBoxHeader(bytes.data() + pos, bytes.size() - pos, pos, "edit"));
    if (h.size > bytes.size() - pos) return Truncated("edit: box runs past the end");
    EditBox b;
    b.type = h.type;
    b.version = h.version;
    b.flags = h.flags;
    b.large = h.header_size == kMaxBoxHeaderSize;
    b.payload.assign(bytes.begin() + pos + h.header_size, bytes.begin() + pos + h.size);
    boxes.push_back(std::move(b));
    pos += h.size;
  }
  return boxes;
}

std::vector<uint8_t> JoinBoxes(const std::vector<EditBox>& boxes) {
  std::vector<uint8_t> out;
  for (const EditBox& b : boxes) {
    if (!b.large) {
      AppendBox(b.type, b.version, b.flags, b.payload, &out);
      continue;
    }
    const uint64_t size = b.payload.size() + kMaxBoxHeaderSize;
    std::vector<uint8_t> header(kMaxBoxHeaderSize);
    StoreLe(&header, 0, 1, 4);
    StoreLe(&header, 4, b.type, 4);
    StoreLe(&header, 8, size, 8);
    StoreLe(&header, 16, b.version, 1);
    StoreLe(&header, 17, b.flags, 3);
    out.insert(out.end(), header.begin(), header.end());
    out.insert(out.end(), b.payload.begin(), b.payload.end());
  }
  return out;
}

uint64_t BoxOffset(const std::vector<EditBox>& boxes, size_t i) {
  uint64_t offset = 0;
  for (size_t k = 0; k < i && k < boxes.size(); ++k) {
    offset += boxes[k].payload.size() + (boxes[k].large ? kMaxBoxHeaderSize : kMinBoxHeaderSize);
  }
  return offset;
}

int FindBox(const std::vector<EditBox>& boxes, FourCC type, int n) {
  for (size_t i = 0; i < boxes.size(); ++i) {
    if (boxes[i].type == type && n-- == 0) return static_cast<int>(i);
  }
  return -1;
}

Status EditFragment(EditBox* fragment, const std::function<void(std::vector<EditBox>*)>& edit) {
  FVV_ASSIGN_OR_RETURN(std::vector<EditBox> subs, SplitBoxes(fragment->payload));
  if (subs.empty() || subs.back().type != box::kChecksum) {
    return Corrupt("edit: fragment does not end with fcrc");
  }
  const EditBox crc_box = subs.back();
  subs.pop_back();
  edit(&subs);
  std::vector<uint8_t> payload = JoinBoxes(subs);
  std::vector<uint8_t> crc(4);
  StoreLe(&crc, 0, Crc32c(payload.data(), payload.size()), 4);
  AppendBox(box::kChecksum, crc_box.version, crc_box.flags, crc, &payload);
  fragment->payload = std::move(payload);
  return Status::Ok();
}

Status EditChunkedFragment(EditBox* fragment,
                           const std::function<void(std::vector<EditBox>*)>& head,
                           const std::function<void(std::vector<uint8_t>*)>& chunks) {
  FVV_ASSIGN_OR_RETURN(std::vector<EditBox> subs, SplitBoxes(fragment->payload));
  if (subs.size() < 2 || subs.back().type != box::kTextureChunks ||
      subs[subs.size() - 2].type != box::kChecksum) {
    return Corrupt("edit: fragment does not end with fcrc and txck");
  }
  EditBox chunk_box = subs.back();
  const EditBox crc_box = subs[subs.size() - 2];
  subs.resize(subs.size() - 2);
  if (head) head(&subs);
  if (chunks) chunks(&chunk_box.payload);
  std::vector<uint8_t> payload = JoinBoxes(subs);
  std::vector<uint8_t> crc(4);
  StoreLe(&crc, 0, Crc32c(payload.data(), payload.size()), 4);
  AppendBox(box::kChecksum, crc_box.version, crc_box.flags, crc, &payload);
  AppendBox(chunk_box.type, chunk_box.version, chunk_box.flags, chunk_box.payload, &payload);
  fragment->payload = std::move(payload);
  return Status::Ok();
}

void RechecksumChunk(std::vector<uint8_t>* chunks, size_t at) {
  const size_t size = size_t(LoadLe(*chunks, at + 1, 2));
  const uint8_t* p = chunks->data() + at;
  StoreLe(chunks, at + 3, Crc32c(p + 7, size, Crc32c(p, 3)), 4);
}

Status DropIndex(std::vector<EditBox>* boxes) {
  const int index = FindBox(*boxes, box::kIndex);
  if (index >= 0) boxes->erase(boxes->begin() + index);
  const int header = FindBox(*boxes, box::kFileHeader);
  if (header < 0) return Corrupt("edit: no fvvh");
  StoreLe(&(*boxes)[header].payload, fvvh::kIndexOffset, 0, 8);
  return Status::Ok();
}

uint64_t LoadLe(const std::vector<uint8_t>& payload, size_t offset, int bytes) {
  uint64_t v = 0;
  for (int i = bytes - 1; i >= 0; --i) {
    const size_t at = offset + size_t(i);
    v = (v << 8) | (at < payload.size() ? payload[at] : 0);
  }
  return v;
}

void StoreLe(std::vector<uint8_t>* payload, size_t offset, uint64_t value, int bytes) {
  for (int i = 0; i < bytes; ++i) (*payload)[offset + i] = static_cast<uint8_t>(value >> (8 * i));
}

}  // namespace fvv
