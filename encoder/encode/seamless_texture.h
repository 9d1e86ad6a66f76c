// Seamless texture recovery: one texture of the actor in
// the atlas from all cameras of a frame. Each triangle takes its texels from
// its best visible camera (the one facing it most squarely among those whose
// resampled texture holds the texel); the cameras' textures are then joined
// by multi-resolution spline blending (Burt and Adelson: Laplacian pyramids of
// the textures mixed with Gaussian pyramids of the camera regions), so the
// blend across a boundary is as wide as the detail it joins is coarse: coarse
// shading and colour differences between cameras fade over many texels, fine
// detail switches within a few, and no seam shows.
//
// Over several frames the seamless textures average into a static texture of
// the actor; the encoder uses the running one as a fallback for texels no
// camera of a frame sees.
#ifndef FVV_ENCODER_ENCODE_SEAMLESS_TEXTURE_H_
#define FVV_ENCODER_ENCODE_SEAMLESS_TEXTURE_H_

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "container/body_model.h"
#include "container/cameras.h"
#include "encoder/encode/resample.h"

namespace fvv {

// One frame's per-camera atlas textures (RGB8, size * size * 3) and masks
// (size * size, 1 = the camera saw the texel), as ResampleView writes them.
struct CameraTextures {
  uint32_t size = 0;
  std::vector<const uint8_t*> rgb, masks;
};

// Per texel: the camera whose texture it is taken from (-1: no camera saw it).
// `positions` and `normals` are the atlas mesh posed for the frame.
std::vector<int16_t> BestCameraLabels(const TexelMap& map, const Mesh& mesh,
                                      const std::vector<Eigen::Vector3f>& positions,
                                      const std::vector<Camera>& cameras,
                                      const CameraTextures& textures);

// The labelled texels composited hard (each from its camera): what blending
// improves on, and a reference for tests.
std::vector<uint8_t> CompositeLabels(const CameraTextures& textures,
                                     const std::vector<int16_t>& labels);

// Multi-resolution spline blend of the cameras' textures over the label
// regions: RGB8 (size * size * 3); texels without a label are 0. `levels` is
// the pyramid depth (0: down to about 4 texels).
std::vector<uint8_t> BlendSeamless(const CameraTextures& textures,
                                   const std::vector<int16_t>& labels, int levels = 0);

// Frames' seamless textures averaged texel by texel over the frames that
// labelled it.
class StaticTexture {
 public:
  explicit StaticTexture(uint32_t size);
  uint32_t size() const { return size_; }
  void Add(const std::vector<uint8_t>& rgb, const std::vector<int16_t>& labels);
  // Replaces it by a texture made before (Rgb() and Coverage() of another).
  void Set(const std::vector<uint8_t>& rgb, const std::vector<uint8_t>& coverage);
  bool Has(size_t texel) const { return count_[texel] > 0; }
  // The mean colour of a texel (Has(texel) must hold).
  void Get(size_t texel, uint8_t* rgb) const;
  // The whole texture (texels never seen are 0) and its coverage (0/1).
  std::vector<uint8_t> Rgb() const;
  std::vector<uint8_t> Coverage() const;

 private:
  uint32_t size_;
  std::vector<float> sum_;
  std::vector<uint32_t> count_;
};

}  // namespace fvv

#endif  // FVV_ENCODER_ENCODE_SEAMLESS_TEXTURE_H_
