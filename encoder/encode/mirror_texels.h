// The body's left-right symmetry in the atlas. A person's clothing and skin
// are mostly alike on both sides, so a texel that no camera has seen in any
// frame so far can take the colour its mirror on the other side was seen
// with, where otherwise only a fill from the texels around it is left. Near
// what the cameras saw that local fill is the better guess (it continues the
// colour there, and a mirror's shading differs); deeper inside an unseen
// region the mirror is (docs/encoder.md has the figures).
#ifndef FVV_ENCODER_ENCODE_MIRROR_TEXELS_H_
#define FVV_ENCODER_ENCODE_MIRROR_TEXELS_H_

#include <cstdint>
#include <utility>
#include <vector>

#include "container/body_model.h"
#include "encoder/encode/resample.h"

namespace fvv {

// Per entry of `map`: the entry whose bind-pose position is nearest the
// entry's own mirrored across the model's x = 0 plane (the plane the body
// model is built symmetric about), or -1 where none lies within
// `max_distance` metres, where the nearest faces another way than the
// mirrored surface, or where the texel lies on the plane (its own mirror).
std::vector<int32_t> MirrorTexels(const TexelMap& map, const Mesh& mesh,
                                  float max_distance = 0.02f);

// How far (4-neighbour steps in the atlas) a texel must lie from every texel
// the cameras' textures hold to take its mirror's colour: 6 at the default
// atlas of 512, in proportion at other sizes.
uint32_t MirrorFillGap(uint32_t atlas_size);

// The texels of one frame to fill from their mirrors, as (entry, mirror
// entry) pairs of `map`: those not `held` (per texel, y * size + x: nonzero
// where some camera's texture of the frame holds it, seen or filled from
// other frames), further than `gap` steps from any held texel, whose mirror
// a camera `seen` in the frame (per texel as `held`; `mirror` from
// MirrorTexels).
std::vector<std::pair<uint32_t, uint32_t>> MirrorFillTargets(const TexelMap& map,
                                                             const std::vector<int32_t>& mirror,
                                                             const std::vector<uint8_t>& held,
                                                             const std::vector<uint8_t>& seen,
                                                             uint32_t gap);

}  // namespace fvv

#endif  // FVV_ENCODER_ENCODE_MIRROR_TEXELS_H_
