// The zstd frames in the WebAssembly build: the frame header read here (RFC
// 8878, 3.1.1), the decompression done by the page's zstd decompressor (the
// npm package fzstd, which Module.fvvZstdDecompress calls), and the content
// checksum, which fzstd does not check, checked here as libzstd checks it.
#include <emscripten.h>

#include "container/zstd_frame.h"

// Decompresses src into dst; the bytes written, or -1 when the data does not
// decode or does not fit. (JavaScript: clang-format would space its operators.)
// clang-format off
EM_JS(int, fvv_web_zstd_decompress, (const uint8_t* src, int src_size, uint8_t* dst, int dst_size), {
  try {
    const out = Module.fvvZstdDecompress(HEAPU8.subarray(src, src + src_size),
                                         HEAPU8.subarray(dst, dst + dst_size));
    if (out.length > dst_size) return -1;
    if (out.byteOffset != dst) HEAPU8.set(out, dst);
    return out.length;
  } catch (e) {
    return -1;
  }
});
// clang-format on

namespace fvv {
namespace {

struct FrameHeader {
  uint64_t content_size = 0;
  bool has_content_size = false;
  bool has_checksum = false;
};

Status ParseFrameHeader(const uint8_t* data, size_t size, FrameHeader* h) {
  if (size < 6 || data[0] != 0x28 || data[1] != 0xB5 || data[2] != 0x2F || data[3] != 0xFD) {
    return Corrupt("not a zstd frame");
  }
  const uint8_t descriptor = data[4];
  const int fcs_flag = descriptor >> 6;
  const bool single_segment = (descriptor >> 5) & 1;
  if (descriptor & 0x08) return Corrupt("zstd frame header sets its reserved bit");
  h->has_checksum = (descriptor >> 2) & 1;
  static const int kDictBytes[4] = {0, 1, 2, 4};
  static const int kFcsBytes[4] = {0, 2, 4, 8};
  size_t at = 5 + (single_segment ? 0 : 1) + size_t(kDictBytes[descriptor & 3]);
  const int fcs_bytes = fcs_flag == 0 && single_segment ? 1 : kFcsBytes[fcs_flag];
  if (at + size_t(fcs_bytes) > size) return Corrupt("zstd frame header cut off");
  h->has_content_size = fcs_bytes > 0;
  uint64_t v = 0;
  for (int i = fcs_bytes - 1; i >= 0; --i) v = (v << 8) | data[at + size_t(i)];
  h->content_size = fcs_bytes == 2 ? v + 256 : v;
  return Status::Ok();
}

}  // namespace

StatusOr<uint64_t> ZstdContentSize(const uint8_t* data, size_t size) {
  FrameHeader h;
  FVV_RETURN_IF_ERROR(ParseFrameHeader(data, size, &h));
  if (!h.has_content_size) return Corrupt("the zstd frame declares no size");
  return h.content_size;
}

Status ZstdDecompress(const uint8_t* data, size_t size, std::vector<uint8_t>* out) {
  FrameHeader h;
  FVV_RETURN_IF_ERROR(ParseFrameHeader(data, size, &h));
  const int n = fvv_web_zstd_decompress(data, int(size), out->data(), int(out->size()));
  if (n < 0) return Corrupt("zstd: the frame does not decode");
  if (size_t(n) != out->size()) return Corrupt("zstd: short output");
  if (h.has_checksum) {
    // The last 4 bytes of the frame: the low 32 bits of XXH64 of the content.
    const uint32_t stored = uint32_t(data[size - 4]) | (uint32_t(data[size - 3]) << 8) |
                            (uint32_t(data[size - 2]) << 16) | (uint32_t(data[size - 1]) << 24);
    if (uint32_t(Xxh64(out->data(), out->size())) != stored) {
      return Corrupt("zstd: Restored data doesn't match checksum");
    }
  }
  return Status::Ok();
}

}  // namespace fvv
