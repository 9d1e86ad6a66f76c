// How much of the reference player's blend (container/geometric_visibility.h)
// a camera's texel can ever be. A stream without masks lets a player take a
// texel from every camera the geometry says sees it; where one camera's weight
// stays a small part of the blend from every viewpoint, what it holds there
// barely shows, and the texture coder's bytes are better spent elsewhere.
#ifndef FVV_ENCODER_ENCODE_BLEND_SHARE_H_
#define FVV_ENCODER_ENCODE_BLEND_SHARE_H_

#include <Eigen/Core>
#include <cstdint>

namespace fvv {

// Camera `c`'s largest share of the blend at a surface point, over every
// viewpoint: its share with the eye on its own direction, where its
// viewing-angle term is largest and the others' fall off least (near 0 the
// term falls far faster than at the angles between cameras). `to_camera`: unit
// directions from the point to each of `n` cameras; `facing`: the cosines
// between the point's normal and them; `takes`: non-zero for the cameras a
// player may take the point from (`c` among them). 0 when `c` has no weight.
double LargestBlendShare(uint32_t c, uint32_t n, const Eigen::Vector3f* to_camera,
                         const double* facing, const uint8_t* takes);

// The same from each camera's facing weight (BlendFacingWeight of its
// cosine), worked out once for every camera at the point.
double LargestBlendShareOfWeights(uint32_t c, uint32_t n, const Eigen::Vector3f* to_camera,
                                  const double* weight, const uint8_t* takes);

// A camera's blend weight at a point without the viewing-angle term: the
// facing ramp times max(facing, 1e-3)^kFacingExponent; 0 facing away.
double BlendFacingWeight(double facing);

}  // namespace fvv

#endif  // FVV_ENCODER_ENCODE_BLEND_SHARE_H_
