// Fuzz target: the mask decoder. Bytes 0-3 give the shape (frames 1-8,
// cameras 1-4, height and width 1-64), the low bit of byte 0's high nibble the
// mode (1 or 2); the rest is coded mask data.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "codec/mask.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 4) return 0;
  fvv::Shape4D shape;
  shape.n = {1u + data[0] % 8, 1u + data[1] % 4, 1u + data[2] % 64, 1u + data[3] % 64};
  std::vector<uint8_t> out(shape.count());
  const auto mode = (data[0] & 0x10) ? fvv::MaskCoding::kMixing : fvv::MaskCoding::kContext;
  (void)fvv::DecodeMasks(data + 4, size - 4, shape, mode, out.data());
  return 0;
}
