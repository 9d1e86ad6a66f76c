// Renderer I: the posed model textured directly from the
// capture's camera images by projective texturing. Every camera's image is
// projected onto the model through its calibration (lens distortion included);
// per-vertex blending weights, computed by the caller from visibility and the
// angle between the normal and each camera, mix the projections; silhouettes
// (the images' alpha) keep the studio background off the model. A preview of a
// capture before encoding and a reference for Renderer II, which textures from
// the coded atlas instead.
//
// Drawn in passes into a floating-point accumulation target: a depth pass,
// then one additive pass per camera (colour times weight, and the weight),
// then a resolve that divides by the summed weight. So any number of cameras
// blend, and a fragment's weights are normalised exactly after the silhouette
// test removed some. OpenGL 3.3 core; the context belongs to the caller.
#ifndef FVV_PLAYER_RENDER_PROJECTIVE_RENDERER_H_
#define FVV_PLAYER_RENDER_PROJECTIVE_RENDERER_H_

#include <cstdint>
#include <memory>
#include <vector>

#include "codec/base/status.h"
#include "fvv/fvv_decoder.h"
#include "player/render/gl_api.h"
#include "player/render/renderer.h"

namespace fvv {

class ProjectiveRenderer {
 public:
  // `triangles` index `vertex_count` vertices (3 per triangle); the cameras
  // fix the image sizes SetFrame takes. The GL context must be current.
  static StatusOr<std::unique_ptr<ProjectiveRenderer>> Create(
      const GlApi& gl, const std::vector<uint32_t>& triangles, uint32_t vertex_count,
      const std::vector<fvv_camera>& cameras);
  ~ProjectiveRenderer();
  ProjectiveRenderer(const ProjectiveRenderer&) = delete;
  ProjectiveRenderer& operator=(const ProjectiveRenderer&) = delete;

  // One frame: posed vertex positions (world, xyz per vertex), blending weights
  // camera-major ([camera][vertex]), and per camera its image as RGBA8 rows,
  // straight, top-down: alpha 255 on the (expanded) silhouette, 0 where a
  // camera has nothing, and kFarFillAlpha where its colour only fills what no
  // silhouette covers (ExpandSilhouette, encoder/shape/projective_texturing.h).
  Status SetFrame(const std::vector<float>& positions, const std::vector<float>& weights,
                  const std::vector<const uint8_t*>& images);
  // RenderView.exponent is not used: the weights carry the blending.
  Status Draw(const RenderView& view, int width, int height);
  // The default framebuffer as top-down RGB8.
  Status ReadRgb(int width, int height, std::vector<uint8_t>* rgb);

 private:
  explicit ProjectiveRenderer(const GlApi& gl) : gl_(gl) {}
  Status CheckGl(const char* where);
  Status PrepareTarget(int width, int height);

  GlApi gl_;
  std::vector<fvv_camera> cameras_;
  uint32_t vertices_ = 0;
  GLsizei index_count_ = 0;
  GLuint accumulate_ = 0, resolve_ = 0;  // programs
  GLuint vao_ = 0, empty_vao_ = 0, positions_ = 0, weights_ = 0, ibo_ = 0;
  std::vector<GLuint> images_;  // one RGBA8 texture per camera
  std::vector<uint8_t> used_;   // per camera: some vertex weighs it this frame
  GLuint framebuffer_ = 0, accumulation_ = 0, depth_ = 0;
  int target_width_ = 0, target_height_ = 0;
  bool has_frame_ = false;
};

}  // namespace fvv

#endif  // FVV_PLAYER_RENDER_PROJECTIVE_RENDERER_H_
