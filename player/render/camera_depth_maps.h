// Every capture camera's depth map of the posed model, on the GPU, for
// streams without shape masks: Renderer II then takes a camera's colour for a
// surface point only where the camera faces it and its depth map does not hide
// it (container/geometric_visibility.h). One R32F layer per camera of a
// texture array, camera z in metres (no surface: far beyond any), the longer
// side kDepthMapLongSide texels; and a std140 block "DepthCameras" that the
// fragment shader projects with:
//   mat4 world_to_camera[64];  // OpenCV camera axes (x right, y down, z forward)
//   vec4 projection[64];       // fx / width, fy / height, (cx + 0.5) / width,
//                              // (cy + 0.5) / height: pinhole to [0, 1], top row 0
//   vec4 texel_angle[64];      // x: radians one depth-map texel spans
// Lens distortion is left out: the maps only decide what hides what.
#ifndef FVV_PLAYER_RENDER_CAMERA_DEPTH_MAPS_H_
#define FVV_PLAYER_RENDER_CAMERA_DEPTH_MAPS_H_

#include <cstdint>
#include <memory>
#include <vector>

#include "codec/base/status.h"
#include "fvv/fvv_decoder.h"
#include "player/render/gl_api.h"

namespace fvv {

class CameraDepthMaps {
 public:
  // The GL context must be current; `cameras` at most 64.
  static StatusOr<std::unique_ptr<CameraDepthMaps>> Create(const GlApi& gl,
                                                           const std::vector<fvv_camera>& cameras);
  ~CameraDepthMaps();
  CameraDepthMaps(const CameraDepthMaps&) = delete;
  CameraDepthMaps& operator=(const CameraDepthMaps&) = delete;

  // Draws the mesh bound in `vao` (the skinning shader's attributes for
  // `vertex_count` vertices, triangles in index buffer `ibo` of `index_count`
  // indices, its bones in uniform buffer `bones_ubo`) into the layer of every
  // camera whose bit `cameras` sets. The mesh is skinned once for all of them
  // (transform feedback), not in every camera's pass. Leaves the default
  // framebuffer bound and the viewport to the caller.
  Status Render(GLuint vao, GLsizei vertex_count, GLuint ibo, GLsizei index_count, GLuint bones_ubo,
                uint64_t cameras);
  // Binds the texture array to texture unit `unit` and the block to uniform
  // buffer binding `binding`.
  void Bind(GLint unit, GLuint binding) const;
  // One camera's map as rendered last, top row first (as the camera's image),
  // width() x height() camera z values; leaves the default framebuffer bound.
  Status ReadLayer(uint32_t camera, std::vector<float>* depth);
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  explicit CameraDepthMaps(const GlApi& gl) : gl_(gl) {}

  GlApi gl_;
  std::vector<fvv_camera> cameras_;
  std::vector<float> view_proj_;  // per camera, column-major mat4
  int width_ = 0, height_ = 0;
  GLuint program_ = 0, skin_program_ = 0, texture_ = 0, framebuffer_ = 0, depth_ = 0, block_ = 0;
  GLuint skinned_ = 0, skinned_vao_ = 0;  // the posed vertices, and a VAO drawing them
  GLsizei skinned_vertices_ = 0;
};

}  // namespace fvv

#endif  // FVV_PLAYER_RENDER_CAMERA_DEPTH_MAPS_H_
