// Reading and writing 8-bit images: PNG through libpng, EXR through OpenEXR;
// JPEG (read only: studios deliver image sequences in it) through libjpeg-turbo.
// Writers go through a temporary file and a rename, so an interrupted write
// never leaves a partial file under the final name.
#ifndef FVV_ENCODER_IO_IMAGE_IO_H_
#define FVV_ENCODER_IO_IMAGE_IO_H_

#include <cstdint>
#include <string>
#include <vector>

#include "codec/base/atomic_file.h"
#include "codec/base/status.h"

namespace fvv {

struct Image {
  uint32_t width = 0, height = 0;
  int channels = 3;  // 1 (grey) or 3 (RGB), interleaved
  std::vector<uint8_t> pixels;
};

// PNG (any bit depth/colour type, converted to 8-bit grey or RGB; alpha dropped)
// or EXR (R, G, B or Y channels, linear values clamped to [0, 1] and scaled to 8 bits)
// or JPEG (.jpg, .jpeg: 8-bit grey or colour; a damaged or truncated stream is an error).
StatusOr<Image> ReadImage(const std::string& path);
Status WritePng(const std::string& path, const Image& image);
Status WriteExr(const std::string& path, const Image& image);
// By extension: .png or .exr.
Status WriteImage(const std::string& path, const Image& image);

// Tiles images (RGB or grey, shown as RGB) into a grid `columns` wide, each
// cell the size of the largest tile, left-aligned and top-aligned, black between.
// columns = 0: about square.
Image MakeContactSheet(const std::vector<Image>& tiles, uint32_t columns = 0);

// Creates `path` and any missing parents (mkdir -p); fine if it exists.
Status MakeDirectories(const std::string& path);

// Whole-file helpers with the same atomic-write rule.
StatusOr<std::vector<uint8_t>> ReadFileBytes(const std::string& path, uint64_t max_bytes);

}  // namespace fvv

#endif  // FVV_ENCODER_IO_IMAGE_IO_H_
