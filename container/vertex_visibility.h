// Optional per-vertex visibility of a fragment ('vvis', SPEC.md 8): which mesh
// vertices each camera saw in each frame, so a player can skip its own
// visibility passes. One bit per (frame, camera, vertex), range coded with the
// same vertex in the previous frame and the previous vertex as context.
#ifndef FVV_CONTAINER_VERTEX_VISIBILITY_H_
#define FVV_CONTAINER_VERTEX_VISIBILITY_H_

#include <cstdint>
#include <vector>

#include "codec/base/status.h"

namespace fvv {

// bits: frames * cameras * vertices bytes (0/1), vertex fastest.
std::vector<uint8_t> EncodeVertexVisibility(const std::vector<uint8_t>& bits, uint32_t frames,
                                            uint32_t cameras, uint32_t vertices);
Status DecodeVertexVisibility(const uint8_t* data, size_t size, uint32_t frames, uint32_t cameras,
                              uint32_t vertices, std::vector<uint8_t>* bits);

}  // namespace fvv

#endif  // FVV_CONTAINER_VERTEX_VISIBILITY_H_
