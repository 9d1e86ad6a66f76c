// Reads a whole stream and decodes every payload (motion, masks, vertex
// visibility, texture): what the whole-file fuzz target and the robustness tests
// run. Returns the first error; never crashes on any input.
#ifndef FVV_FUZZ_DECODE_ALL_H_
#define FVV_FUZZ_DECODE_ALL_H_

#include <cstdint>
#include <vector>

#include "codec/base/status.h"

namespace fvv {

struct DecodeAllReport {
  uint64_t fragments = 0;
  uint64_t frames = 0;
  uint64_t hash = 0;  // FNV-1a over decoded poses, masks and texture samples
};

// chunk: bytes pushed per call to the incremental reader (0 = all at once).
Status DecodeAll(const uint8_t* data, size_t size, size_t chunk, DecodeAllReport* report);

}  // namespace fvv

#endif  // FVV_FUZZ_DECODE_ALL_H_
