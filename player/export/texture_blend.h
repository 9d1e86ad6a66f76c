// One colour texture from a stream's camera textures: each atlas texel is the
// average of what the cameras that saw it recorded, over the frames added,
// weighted by how squarely they saw the surface there (the cosine between its
// normal and the direction to the camera, squared); where the stream has no
// masks, "saw" is the geometric rule a player follows (facing, and not hidden
// in the camera's depth map of the posed model: container/geometric_visibility.h);
// texels no camera saw take
// the colour of the nearest texels that have one, so that filtering and
// mipmapping across chart borders find no black.
#ifndef FVV_PLAYER_EXPORT_TEXTURE_BLEND_H_
#define FVV_PLAYER_EXPORT_TEXTURE_BLEND_H_

#include <glm/vec3.hpp>
#include <vector>

#include "fvv/fvv_decoder.h"

namespace fvv {

class TextureBlend {
 public:
  // model: the decoder's; cameras: the stream's.
  TextureBlend(const fvv_model& model, uint32_t width, uint32_t height,
               std::vector<fvv_camera> cameras);
  // A decoded frame in RGB8 (cameras left out by a camera mask are skipped).
  // Where the stream has masks a camera counts where its mask says it saw the
  // texel; without masks, where the geometry lets a player take it.
  void Add(const fvv_frame& frame);
  // The texture, size x size (0: the atlas's size), RGB8, row 0 at v = 0.
  std::vector<uint8_t> Finish(uint32_t size) const;
  // Whether any camera's sample reached atlas texel i (before filling).
  bool Seen(size_t i) const { return weight_[i] > 0; }

 private:
  const fvv_model& model_;
  uint32_t width_, height_;
  std::vector<fvv_camera> cameras_;
  std::vector<glm::vec3> centres_;
  // Texels inside the mesh's UV triangles: texel index, triangle, barycentrics.
  std::vector<uint32_t> texel_, triangle_;
  std::vector<glm::vec3> bary_;
  std::vector<float> sum_;     // [texel][3] weighted colour
  std::vector<float> weight_;  // [texel]
};

}  // namespace fvv

#endif  // FVV_PLAYER_EXPORT_TEXTURE_BLEND_H_
