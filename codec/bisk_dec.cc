#include <algorithm>

#include "codec/bisk.h"
#include "codec/bisk_common.h"

namespace fvv {

Status BiskDecode(const uint8_t* data, size_t size, WaveletKernel kernel, int levels,
                  ShapePlane* image, BiskDecodeInfo* info,
                  const std::vector<std::vector<uint8_t>>* stage_masks) {
  const size_t n = size_t(image->width) * image->height;
  if (image->mask.size() != n) return InvalidArgument("BISK: the shape is not width x height");
  const std::vector<uint8_t> shape = image->mask;
  image->samples.assign(n, 0);
  BiskDecodeInfo local;
  if (size == 0) {
    local.truncated = true;
    if (info) *info = local;
    return Status::Ok();
  }
  if (data[0] == 255) {
    if (info) *info = local;
    return Status::Ok();
  }
  if (data[0] > 30) return Corrupt("BISK: top bitplane " + std::to_string(data[0]) + " > 30");
  const int top = data[0];
  // The coefficients' layout is the shape's, transformed.
  std::vector<std::vector<uint8_t>> own_masks;
  if (stage_masks == nullptr) {
    own_masks = ShapeAdaptiveMasks(shape, image->width, image->height, levels);
    stage_masks = &own_masks;
  }
  const std::vector<uint8_t>& layout = stage_masks->back();
  RangeDecoder dec(data + 1, size - 1);
  bisk::BiskCoder<false> coder(image->width, image->height, layout, levels, image->samples.data(),
                               nullptr, &dec);
  local.planes_completed = coder.Run(top);
  local.truncated = local.planes_completed < top + 1;
  coder.Reconstruct();
  // Back from the coding scale, to the nearest integer.
  const bisk::SubbandShifts shifts(image->width, image->height, levels);
  for (uint32_t y = 0; y < image->height; ++y) {
    for (uint32_t x = 0; x < image->width; ++x) {
      const int shift = shifts(x, y);
      int32_t& c = image->samples[size_t(y) * image->width + x];
      // 64-bit: a magnitude near 2^31 plus the rounding would overflow.
      const int64_t v = c, half = (int64_t(1) << shift) >> 1;
      c = int32_t(v >= 0 ? (v + half) >> shift : -((-v + half) >> shift));
    }
  }
  image->mask = layout;
  InverseShapeAdaptive(kernel, levels, *stage_masks, image);
  for (size_t i = 0; i < n; ++i) {
    if (!shape[i]) image->samples[i] = 0;
  }
  if (info) *info = local;
  return Status::Ok();
}

}  // namespace fvv
