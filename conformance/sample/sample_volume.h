// A built-in multi-view test volume, so the demo and tests need no data files:
// a textured, lit scene seen by a ring of cameras (each a shifted, slightly
// rescaled view) over frames of a slow pan, with an elliptical "actor" mask per view.
#ifndef FVV_CONFORMANCE_SAMPLE_SAMPLE_VOLUME_H_
#define FVV_CONFORMANCE_SAMPLE_SAMPLE_VOLUME_H_

#include <cstdint>

#include "encoder/io/image_io.h"

namespace fvv {

Image SampleView(uint32_t frame, uint32_t camera, uint32_t width, uint32_t height);
Image SampleMask(uint32_t frame, uint32_t camera, uint32_t width, uint32_t height);

}  // namespace fvv

#endif  // FVV_CONFORMANCE_SAMPLE_SAMPLE_VOLUME_H_
