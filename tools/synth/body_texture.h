// The built-in actor's procedural clothing and skin: a T-shirt with stripes and
// a chest logo, jeans with a belt, shoes, skin with a face and hair, each with
// fabric-scale noise so textures carry real detail. Baked into the generic body
// model's chart layout, so the texture is an ordinary image (the ground truth
// the encoder's resampling is checked against).
#ifndef FVV_TOOLS_SYNTH_BODY_TEXTURE_H_
#define FVV_TOOLS_SYNTH_BODY_TEXTURE_H_

#include <Eigen/Core>
#include <vector>

#include "container/body_model.h"
#include "encoder/io/image_io.h"

namespace fvv {

// The colour of the built-in actor's surface at rest-pose point `p` (metres) of
// `segment`, with outward normal `n`; `rest_joints` are the generic body's rest
// joint positions (features are placed relative to them).
Eigen::Vector3f ClothingColour(const std::vector<Eigen::Vector3d>& rest_joints, int segment,
                               const Eigen::Vector3d& p, const Eigen::Vector3d& n, uint32_t seed);

// Bakes ClothingColour into a size x size RGB texture over the model's UVs;
// texels outside every chart are filled from the nearest chart texel, so
// bilinear sampling at chart borders does not pick up unrelated colours.
Image BakeBodyTexture(const BodyModel& model, int size, uint32_t seed);

}  // namespace fvv

#endif  // FVV_TOOLS_SYNTH_BODY_TEXTURE_H_
