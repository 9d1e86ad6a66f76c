// Fuzz target: the poses.json / truth.json parser behind `fvv encode --poses`.
#include <cstddef>
#include <cstdint>
#include <string>

#include "encoder/encode/pose_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  (void)fvv::ParsePoseFile(text, "poses.json");
  return 0;
}
