// Renderer II: the body model skinned into the decoded pose and textured from
// every camera's atlas texture, blended per fragment by viewing angle:
// camera i's weight is its visibility at the texel
// times (1 / (angle(view direction, camera direction) + eps))^exponent
// times cos(angle(normal, camera direction))^facing_exponent, normalised; where no camera saw a
// texel the best-facing camera fills in. The visibility is the stream's mask where it has masks;
// without, it comes from the geometry: each camera's depth map of the posed model
// (camera_depth_maps.h), rendered once per frame for the cameras the view
// blends. OpenGL 3.3 core; the context (OSMesa or GLFW) belongs to the caller.
#ifndef FVV_PLAYER_RENDER_RENDERER_H_
#define FVV_PLAYER_RENDER_RENDERER_H_

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <memory>
#include <vector>

#include "codec/base/status.h"
#include "container/geometric_visibility.h"
#include "fvv/fvv_decoder.h"
#include "player/playback/view_cameras.h"
#include "player/render/camera_depth_maps.h"
#include "player/render/gl_api.h"

namespace fvv {

struct RenderView {
  glm::mat4 view{1.0f};
  glm::mat4 projection{1.0f};
  glm::vec3 eye{0.0f};
  // Higher: the best-aligned camera dominates more.
  float exponent = float(geometric_visibility::kViewExponent);
  // Higher: the cameras facing the surface squarely dominate more (their
  // samples are the finest and the least displaced where the model misses the
  // actor); docs/encoder.md, "Streams without masks", on blending.
  float facing_exponent = float(geometric_visibility::kFacingExponent);
  glm::vec3 background{0.12f, 0.12f, 0.14f};
};

class Renderer {
 public:
  // Uploads the mesh; the GL context must be current.
  static StatusOr<std::unique_ptr<Renderer>> Create(const GlApi& gl, const fvv_model& model,
                                                    const std::vector<fvv_camera>& cameras,
                                                    uint32_t atlas_width, uint32_t atlas_height);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Bone matrices, textures and masks of a decoded frame (RGB8). Cameras the
  // decode left out (NULL pixels) take no part in blending.
  Status SetFrame(const fvv_frame& frame);
  Status Draw(const RenderView& view, int width, int height);
  // With `on`, each frame's depth maps are waited for (glFinish) and timed:
  // depth_map_ms() is then the milliseconds they took so far. Off by default,
  // so that a player's CPU does not wait for the GPU.
  void MeasureDepthMaps(bool on) { measure_depth_maps_ = on; }
  double depth_map_ms() const { return depth_map_ms_; }
  // How many camera layers of depth maps were drawn so far; 0 with masks.
  uint64_t depth_map_layers() const { return depth_map_layers_; }
  // The depth maps drawn for the current frame (null before any frame
  // without masks was drawn).
  CameraDepthMaps* depth_maps() const { return depth_maps_.get(); }
  // The framebuffer as top-down RGB8.
  Status ReadRgb(int width, int height, std::vector<uint8_t>* rgb);
  // The pixels the last Draw covered with the actor (255) or left (0), top-down.
  Status ReadCoverage(int width, int height, std::vector<uint8_t>* coverage);

 private:
  explicit Renderer(const GlApi& gl) : gl_(gl) {}
  Status CheckGl(const char* where);
  // The depth maps of `cameras` (bits) for the current frame, where not yet.
  Status RenderDepthMaps(uint64_t cameras);

  GlApi gl_;
  GLuint program_ = 0, depth_program_ = 0, vao_ = 0, vbo_ = 0, ibo_ = 0, bones_ubo_ = 0,
         textures_ = 0, masks_ = 0, positions_vbo_ = 0;
  GLuint depth_map_ibo_ = 0;  // the simplified body the depth maps draw (depth_map_triangles.h)
  GLsizei depth_map_index_count_ = 0;
  std::vector<uint32_t> model_triangles_;  // the model's, until the depth maps' body is made
  std::vector<float> model_positions_;     // the model's bind pose (fvv_model)
  bool positions_are_surface_ = false;     // positions_vbo_ holds a frame's surface
  GLsizei index_count_ = 0;
  uint32_t vertex_count_ = 0;
  uint32_t cameras_ = 0, width_ = 0, height_ = 0, bones_ = 0;
  std::vector<fvv_camera> camera_list_;
  std::vector<glm::vec3> camera_centres_;
  std::unique_ptr<CameraDepthMaps> depth_maps_;  // made on the first frame without masks
  uint64_t depth_rendered_ = 0;                  // cameras whose map holds the current frame
  double depth_map_ms_ = 0;
  uint64_t depth_map_layers_ = 0;
  std::vector<uint8_t> mask_scratch_;
  std::vector<GLint> present_;    // per camera: the current frame carries its texture
  glm::vec3 actor_centre_{0.0f};  // the root joint of the current frame
  bool has_masks_ = false, has_frame_ = false, measure_depth_maps_ = false;
};

// A ready decoder's cameras (what Renderer::Create takes); empty on error.
std::vector<fvv_camera> DecoderCameras(const fvv_decoder* decoder);

// Capture camera -> GL view and projection (OpenCV conventions to GL).
void CameraViewProjection(const fvv_camera& camera, float near_m, float far_m, glm::mat4* view,
                          glm::mat4* projection);

}  // namespace fvv

#endif  // FVV_PLAYER_RENDER_RENDERER_H_
