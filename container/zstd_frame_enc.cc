#include <zstd.h>

#include "container/zstd_frame.h"

namespace fvv {

std::vector<uint8_t> ZstdCompress(const uint8_t* data, size_t size, int level) {
  std::vector<uint8_t> packed(ZSTD_compressBound(size));
  ZSTD_CCtx* cctx = ZSTD_createCCtx();
  ZSTD_CCtx_setParameter(cctx, ZSTD_c_compressionLevel, level);
  ZSTD_CCtx_setParameter(cctx, ZSTD_c_checksumFlag, 1);
  const size_t n = ZSTD_compress2(cctx, packed.data(), packed.size(), data, size);
  ZSTD_freeCCtx(cctx);
  if (ZSTD_isError(n)) return {};
  packed.resize(n);
  return packed;
}

}  // namespace fvv
