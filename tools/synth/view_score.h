// Scores of rendered views against a synthetic capture's truth: the
// generator's own render of a (held-out) camera, over the actor's pixels.
#ifndef FVV_TOOLS_SYNTH_VIEW_SCORE_H_
#define FVV_TOOLS_SYNTH_VIEW_SCORE_H_

#include <cstdint>
#include <string>
#include <vector>

#include "codec/base/status.h"
#include "encoder/io/image_io.h"

namespace fvv {

// RGB PSNR of `rgb` (RGB8, the truth's size) against `truth` over the pixels
// `silhouette` marks; `pixels` (may be null) receives their count.
double ActorPsnr(const std::vector<uint8_t>& rgb, const Image& truth, const Image& silhouette,
                 uint64_t* pixels = nullptr);

// Renderer II's view of frame `frame` of `stream` from held-out camera
// `camera` of the synthetic capture in `capture` (its truth/heldout), scored
// by ActorPsnr against the generator's render of that camera.
StatusOr<double> HeldOutStreamPsnr(const std::string& stream, const std::string& capture,
                                   uint32_t camera, uint32_t frame);

}  // namespace fvv

#endif  // FVV_TOOLS_SYNTH_VIEW_SCORE_H_
