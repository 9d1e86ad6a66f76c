// An RGB8 image as PNG bytes in memory (libpng), for the glTF writer's texture.
#ifndef FVV_PLAYER_EXPORT_PNG_ENCODE_H_
#define FVV_PLAYER_EXPORT_PNG_ENCODE_H_

#include <cstdint>
#include <vector>

#include "codec/base/status.h"

namespace fvv {

StatusOr<std::vector<uint8_t>> EncodePng(const uint8_t* rgb, uint32_t width, uint32_t height);

}  // namespace fvv

#endif  // FVV_PLAYER_EXPORT_PNG_ENCODE_H_
