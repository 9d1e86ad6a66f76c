// Fuzz target: the stand-alone block file (.fvb) parser and the texture decoder
// (wavelet + 4D SPIHT) behind it.
#include <cstddef>
#include <cstdint>

#include "codec/block_codec.h"
#include "codec/block_syntax.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  auto block = fvv::ReadBlockFile(data, size);
  if (!block.ok()) return 0;
  // Keep each run short: the fuzzer should explore syntax, not decode huge blocks.
  if (block->params.shape.count() > (1u << 16)) return 0;
  (void)fvv::DecodeBlock(*block, fvv::DecodeBudget(), fvv::SerialRunner);
  return 0;
}
