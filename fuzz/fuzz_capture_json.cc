// Fuzz target: capture.json (cameras, frame sources, silhouettes, the world's
// up axis) as `fvv capture check` and every command that reads a capture parse
// it. Paths resolve against a directory that does not exist: the parser must
// refuse what it cannot find with an error, not read anything.
#include <cstddef>
#include <cstdint>
#include <string>

#include "encoder/capture/capture.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  (void)fvv::ParseCapture(text, "/nonexistent/fvv_fuzz_capture");
  return 0;
}
