// Fuzz target: whole-stream decoding (box parser, header validation, model,
// motion, masks, vertex visibility, texture), pushed in chunks chosen by byte 0.
#include <cstddef>
#include <cstdint>

#include "fuzz/decode_all.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  fvv::DecodeAllReport report;
  (void)fvv::DecodeAll(data + 1, size - 1, data[0] == 0 ? 0 : data[0], &report);
  return 0;
}
