// Fuzz target: the image readers capture frames, plates and silhouettes go
// through (ReadImage). Byte 0 picks the reader by file name: JPEG, PNG or
// OpenEXR; the rest is the file, written to a temporary directory because the
// readers read files.
#include <cstddef>
#include <cstdint>
#include <string>

#include "encoder/io/image_io.h"
#include "fuzz/temp_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  static const char* const kNames[3] = {"/frame.jpg", "/frame.png", "/frame.exr"};
  const std::string path = fvv::FuzzTempDir() + kNames[data[0] % 3];
  if (!fvv::WriteFuzzFile(path, data + 1, size - 1)) return 0;
  fvv::StatusOr<fvv::Image> image = fvv::ReadImage(path);
  if (image.ok()) {
    // A picture read is whole: every sample of its stated size is there.
    const size_t samples = size_t{image->width} * image->height * size_t(image->channels);
    if (image->pixels.size() != samples || image->width == 0 || image->height == 0)
      __builtin_trap();
  }
  return 0;
}
