// Fuzz target: the BVH motion parser (HIERARCHY and MOTION sections), as
// `fvv synth --motion` and the glTF/BVH importers read it.
#include <cstddef>
#include <cstdint>
#include <string>

#include "encoder/import/bvh.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  (void)fvv::ParseBvh(text, 0.01);
  return 0;
}
