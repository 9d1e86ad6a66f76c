// The decoder's output pixels: one camera's atlas texture of a decoded GOP as
// 8-bit RGB (the normative conversion, SPEC.md 9.7) or planar YUV 4:4:4 bytes.
#ifndef FVV_PLAYER_DECODER_VIEW_PIXELS_H_
#define FVV_PLAYER_DECODER_VIEW_PIXELS_H_

#include <cstdint>
#include <memory>

#include "codec/block.h"

namespace fvv {

enum class ViewFormat { kRgb8, kYuv444 };

// Allocates width * height * 3 bytes (uninitialised, then every byte written):
// interleaved RGB, or the Y, U and V planes one after the other.
void ViewPixels(const Block& block, uint32_t t, uint32_t c, ViewFormat format,
                std::unique_ptr<uint8_t[]>* pixels);

}  // namespace fvv

#endif  // FVV_PLAYER_DECODER_VIEW_PIXELS_H_
