#include "container/zstd_frame.h"

#include <zstd.h>

namespace fvv {

StatusOr<uint64_t> ZstdContentSize(const uint8_t* data, size_t size) {
  const unsigned long long content = ZSTD_getFrameContentSize(data, size);
  if (content == ZSTD_CONTENTSIZE_ERROR) return Corrupt("not a zstd frame");
  if (content == ZSTD_CONTENTSIZE_UNKNOWN) return Corrupt("the zstd frame declares no size");
  return uint64_t{content};
}

Status ZstdDecompress(const uint8_t* data, size_t size, std::vector<uint8_t>* out) {
  const size_t n = ZSTD_decompress(out->data(), out->size(), data, size);
  if (ZSTD_isError(n)) return Corrupt(std::string("zstd: ") + ZSTD_getErrorName(n));
  if (n != out->size()) return Corrupt("zstd: short output");
  return Status::Ok();
}

}  // namespace fvv
