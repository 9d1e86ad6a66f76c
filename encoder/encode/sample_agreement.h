// Whether the cameras that sampled a surface point agree on its colour. A
// camera sees the actor's surface point only if nothing stands between them;
// the geometry knows only the actor's own body, so a bystander or a prop in
// front of him, or the background past an outline the model misses, lands in
// that camera's texture as if it were his. A camera's sample that no other
// camera seeing the point backs saw something else, and is dropped (the texel
// is then unseen by that camera, as if hidden); two cameras that disagree are
// both dropped, since neither can be told right. A point one camera alone
// sees cannot be checked.
#ifndef FVV_ENCODER_ENCODE_SAMPLE_AGREEMENT_H_
#define FVV_ENCODER_ENCODE_SAMPLE_AGREEMENT_H_

#include <cstddef>
#include <cstdint>

namespace fvv {

struct SampleAgreementOptions {
  // A sample differing from the others' median by more than this (mean
  // absolute difference over R, G and B, in levels) saw something else.
  double max_difference = 40;
  // Cameras that must have seen a point for a vote: with two, neither can be
  // told wrong.
  uint32_t min_cameras = 2;
};

struct SampleAgreementCount {
  uint64_t voted = 0;    // texels checked: seen by at least min_cameras cameras
  uint64_t dropped = 0;  // samples dropped
};

// One frame of `cameras` atlas textures, camera-major: `rgb` holds
// cameras x texels x 3 samples, `mask` cameras x texels (non-0: seen).
// `texel_list` (`count` entries): the texels to check (the atlas's charts).
// Clears the mask of every sample no other camera's backs. With `suspects`
// (per camera, may be null): only the samples of the cameras marked there
// are checked, and one that no other camera saw is dropped too (it cannot be
// told the actor's); the other cameras' samples are kept and back them.
SampleAgreementCount DropDisagreeingSamples(uint32_t cameras, size_t texels,
                                            const uint32_t* texel_list, size_t count,
                                            const uint8_t* rgb, uint8_t* mask,
                                            const SampleAgreementOptions& options,
                                            const uint8_t* suspects = nullptr);

}  // namespace fvv

#endif  // FVV_ENCODER_ENCODE_SAMPLE_AGREEMENT_H_
