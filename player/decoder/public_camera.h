// A calibrated camera as the public C API describes it (fvv_camera): what
// fvv_decoder_get_camera returns and what the renderers take.
#ifndef FVV_PLAYER_DECODER_PUBLIC_CAMERA_H_
#define FVV_PLAYER_DECODER_PUBLIC_CAMERA_H_

#include "container/cameras.h"
#include "fvv/fvv_decoder.h"

namespace fvv {

// The name points into `camera`, which must outlive the result.
fvv_camera PublicCamera(const Camera& camera);

}  // namespace fvv

#endif  // FVV_PLAYER_DECODER_PUBLIC_CAMERA_H_
