// The surface of every frame (tool bit 22, SPEC.md 3.5.2): per frame of a
// fragment, each vertex of the body model moved along its bind-pose normal by
// an integer number of steps of 2^-e metres. Skinning carries the moved bind
// pose into the frame's pose, so the skeleton, atlas and topology stay those
// of the model. The values travel as one zstd frame of zigzag LEB128
// residuals: a fragment's first frame predicted from the vertex before (the
// model's vertex order runs along the surface), later frames from the same
// vertex one frame earlier. Encoder and decoder share the prediction.
#ifndef FVV_CONTAINER_SURFACE_DISPLACEMENT_H_
#define FVV_CONTAINER_SURFACE_DISPLACEMENT_H_

#include <cstddef>
#include <cstdint>
#include <vector>

#include "codec/base/status.h"
#include "container/body_model.h"

namespace fvv {

// The head 'sfhd' (SPEC.md 3.5.2).
struct SurfaceHead {
  uint8_t step_exponent = 10;  // a step is 2^-step_exponent metres
  uint32_t vertex_count = 0;   // the model's
  uint32_t data_size = 0;      // bytes of the coded values, in chunks of channel 3
};
constexpr uint8_t kMinSurfaceStepExponent = 6;   // 15.6 mm
constexpr uint8_t kMaxSurfaceStepExponent = 16;  // 15 micrometres
// |value| bound: at step 2^-6 m a value reaches 16 km; the bound keeps the
// arithmetic of SurfacePositions exact.
constexpr int32_t kMaxSurfaceValue = (1 << 20) - 1;
// Each value's residual takes at most 5 bytes (LEB128 of 32 bits).
constexpr uint32_t kMaxSurfaceResidualBytes = 5;

// The prediction of value (frame t, vertex v) from the values before it.
inline int64_t PredictSurfaceValue(const int32_t* values, uint32_t vertices, uint32_t t,
                                   uint32_t v) {
  if (t > 0) return values[size_t(t - 1) * vertices + v];
  return v > 0 ? values[v - 1] : 0;
}

// Decodes `frames` x `vertices` values (frame-major) from the coded bytes;
// Corrupt when the zstd frame is damaged, declares a size beyond
// kMaxSurfaceResidualBytes per value, holds too few or too many residuals, or
// a value exceeds kMaxSurfaceValue.
Status DecodeSurfaceDisplacements(const uint8_t* data, size_t size, uint32_t frames,
                                  uint32_t vertices, std::vector<int32_t>* values);

// The bind-pose positions of one frame: position + value * 2^-e * normal per
// component, the product exact in binary64, the sum rounded to binary64 and
// then to binary32 (SPEC.md 3.5.2). `out` receives vertex_count x 3 floats.
void SurfacePositions(const Mesh& mesh, const int32_t* values, uint8_t step_exponent,
                      std::vector<float>* out);

// The encoder's side (container library only): the coded bytes of `values`
// (`frames` x `vertices`, each within kMaxSurfaceValue).
std::vector<uint8_t> EncodeSurfaceDisplacements(const std::vector<int32_t>& values, uint32_t frames,
                                                uint32_t vertices);

}  // namespace fvv

#endif  // FVV_CONTAINER_SURFACE_DISPLACEMENT_H_
