#include "player/render/camera_depth_maps.h"

#include <algorithm>
#include <glm/gtc/type_ptr.hpp>
#include <string>

#include "container/geometric_visibility.h"
#include "player/render/renderer.h"
#include "player/render/shaders.h"

namespace fvv {
namespace {

constexpr size_t kMaxCameras = 64;
constexpr float kNear = 0.05f, kFar = 100.0f;
constexpr float kNoSurface = 1e9f;
// std140: mat4[64], vec4[64], vec4[64].
constexpr size_t kBlockFloats = kMaxCameras * (16 + 4 + 4);

}  // namespace

StatusOr<std::unique_ptr<CameraDepthMaps>> CameraDepthMaps::Create(
    const GlApi& gl, const std::vector<fvv_camera>& cameras) {
  namespace gv = geometric_visibility;
  if (cameras.empty() || cameras.size() > kMaxCameras) {
    return Unsupported("depth maps: " + std::to_string(cameras.size()) + " cameras (1..64)");
  }
  std::unique_ptr<CameraDepthMaps> d(new CameraDepthMaps(gl));
  d->cameras_ = cameras;
  for (const fvv_camera& c : cameras) {
    if (c.width == 0 || c.height == 0 || !(c.fx > 0) || !(c.fy > 0)) {
      return InvalidArgument("depth maps: a camera without an image size or focal length");
    }
    int w = 0, h = 0;
    gv::DepthMapSize(c.width, c.height, &w, &h);
    d->width_ = std::max(d->width_, w);
    d->height_ = std::max(d->height_, h);
  }
  std::vector<float> block(kBlockFloats, 0.0f);
  for (size_t c = 0; c < cameras.size(); ++c) {
    const fvv_camera& cam = cameras[c];
    glm::mat4 view, projection;
    CameraViewProjection(cam, kNear, kFar, &view, &projection);
    const glm::mat4 vp = projection * view;
    d->view_proj_.insert(d->view_proj_.end(), glm::value_ptr(vp), glm::value_ptr(vp) + 16);
    float* m = &block[c * 16];  // column-major: element (row r, column k) at [k * 4 + r]
    for (int r = 0; r < 3; ++r) {
      for (int k = 0; k < 3; ++k) m[k * 4 + r] = float(cam.rotation[r * 3 + k]);
      m[12 + r] = float(cam.translation[r]);
    }
    m[15] = 1.0f;
    float* p = &block[kMaxCameras * 16 + c * 4];
    p[0] = float(cam.fx / cam.width);
    p[1] = float(cam.fy / cam.height);
    p[2] = float((cam.cx + 0.5) / cam.width);
    p[3] = float((cam.cy + 0.5) / cam.height);
    // The layer spans the whole image: fx * width_ / image width texels per
    // unit of x / z, likewise in y; the coarser of the two.
    const double texels_per_radian =
        std::min(cam.fx * d->width_ / cam.width, cam.fy * d->height_ / cam.height);
    block[kMaxCameras * 20 + c * 4] = float(1.0 / texels_per_radian);
  }

  const GlApi& g = d->gl_;
  StatusOr<GLuint> program =
      BuildProgram(g, shaders::kCameraDepthVert, shaders::kCameraDepthFrag, "camera depth maps");
  if (!program.ok()) return program.status();
  d->program_ = *program;
  program = BuildProgram(g, kSkinningVertexShader, nullptr, "skinning for depth maps", "v_world");
  if (!program.ok()) return program.status();
  d->skin_program_ = *program;
  g.UniformBlockBinding(d->skin_program_, g.GetUniformBlockIndex(d->skin_program_, "Bones"), 0);
  g.GenBuffers(1, &d->skinned_);
  g.GenVertexArrays(1, &d->skinned_vao_);

  g.GenTextures(1, &d->texture_);
  g.BindTexture(GL_TEXTURE_2D_ARRAY, d->texture_);
  g.TexImage3D(GL_TEXTURE_2D_ARRAY, 0, GL_R32F, d->width_, d->height_, GLsizei(cameras.size()), 0,
               GL_RED, GL_FLOAT, nullptr);
  g.TexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  g.TexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  g.TexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  g.TexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  g.GenRenderbuffers(1, &d->depth_);
  g.BindRenderbuffer(GL_RENDERBUFFER, d->depth_);
  g.RenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, d->width_, d->height_);
  g.GenFramebuffers(1, &d->framebuffer_);
  g.BindFramebuffer(GL_FRAMEBUFFER, d->framebuffer_);
  g.FramebufferTextureLayer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, d->texture_, 0, 0);
  g.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, d->depth_);
  const GLenum status = g.CheckFramebufferStatus(GL_FRAMEBUFFER);
  g.BindFramebuffer(GL_FRAMEBUFFER, 0);
  if (status != GL_FRAMEBUFFER_COMPLETE) {
    return Unsupported("depth maps: no R32F render target (framebuffer status " +
                       std::to_string(status) + ")");
  }
  g.GenBuffers(1, &d->block_);
  g.BindBuffer(GL_UNIFORM_BUFFER, d->block_);
  g.BufferData(GL_UNIFORM_BUFFER, GLsizeiptr(block.size() * sizeof(float)), block.data(),
               GL_STATIC_DRAW);
  const GLenum e = g.GetError();
  if (e != GL_NO_ERROR) return Internal("OpenGL error " + std::to_string(e) + " in depth maps");
  return d;
}

CameraDepthMaps::~CameraDepthMaps() {
  if (framebuffer_) gl_.DeleteFramebuffers(1, &framebuffer_);
  if (depth_) gl_.DeleteRenderbuffers(1, &depth_);
  if (texture_) gl_.DeleteTextures(1, &texture_);
  if (block_) gl_.DeleteBuffers(1, &block_);
  if (skinned_) gl_.DeleteBuffers(1, &skinned_);
  if (skinned_vao_) gl_.DeleteVertexArrays(1, &skinned_vao_);
  if (program_) gl_.DeleteProgram(program_);
  if (skin_program_) gl_.DeleteProgram(skin_program_);
}

Status CameraDepthMaps::Render(GLuint vao, GLsizei vertex_count, GLuint ibo, GLsizei index_count,
                               GLuint bones_ubo, uint64_t cameras) {
  const GlApi& g = gl_;
  if (vertex_count != skinned_vertices_) {  // the first frame: the buffer and its VAO
    g.BindBuffer(GL_ARRAY_BUFFER, skinned_);
    g.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(vertex_count) * 12, nullptr, GL_DYNAMIC_COPY);
    g.BindVertexArray(skinned_vao_);
    g.EnableVertexAttribArray(0);
    g.VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 12, nullptr);
    g.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, ibo);
    g.BindVertexArray(0);
    skinned_vertices_ = vertex_count;
  }
  // Skin every vertex once, into `skinned_`.
  g.UseProgram(skin_program_);
  g.Uniform1i(g.GetUniformLocation(skin_program_, "u_skinned"), 1);
  g.BindBufferBase(GL_UNIFORM_BUFFER, 0, bones_ubo);
  g.BindBufferBase(GL_TRANSFORM_FEEDBACK_BUFFER, 0, skinned_);
  g.BindVertexArray(vao);
  g.Enable(GL_RASTERIZER_DISCARD);
  g.BeginTransformFeedback(GL_POINTS);
  g.DrawArrays(GL_POINTS, 0, vertex_count);
  g.EndTransformFeedback();
  g.Disable(GL_RASTERIZER_DISCARD);
  g.BindBufferBase(GL_TRANSFORM_FEEDBACK_BUFFER, 0, 0);
  // Each camera's pass draws the skinned vertices.
  g.BindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  g.Viewport(0, 0, width_, height_);
  g.UseProgram(program_);
  const GLint view_proj = g.GetUniformLocation(program_, "u_view_proj");
  g.BindVertexArray(skinned_vao_);
  g.Enable(GL_DEPTH_TEST);
  g.DepthFunc(GL_LESS);
  g.DepthMask(GL_TRUE);
  g.Enable(GL_CULL_FACE);  // the nearest surface of a closed model faces the camera
  g.ClearColor(kNoSurface, kNoSurface, kNoSurface, kNoSurface);
  for (size_t c = 0; c < cameras_.size(); ++c) {
    if (!((cameras >> c) & 1)) continue;
    g.FramebufferTextureLayer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, texture_, 0, GLint(c));
    g.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    g.UniformMatrix4fv(view_proj, 1, GL_FALSE, &view_proj_[c * 16]);
    g.DrawElements(GL_TRIANGLES, index_count, GL_UNSIGNED_INT, nullptr);
  }
  g.Disable(GL_CULL_FACE);
  g.BindVertexArray(0);
  g.BindFramebuffer(GL_FRAMEBUFFER, 0);
  const GLenum e = g.GetError();
  if (e != GL_NO_ERROR) return Internal("OpenGL error " + std::to_string(e) + " in depth maps");
  return Status::Ok();
}

Status CameraDepthMaps::ReadLayer(uint32_t camera, std::vector<float>* depth) {
  if (camera >= cameras_.size()) return InvalidArgument("depth maps: no such camera");
  const GlApi& g = gl_;
  g.BindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  g.FramebufferTextureLayer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, texture_, 0, GLint(camera));
  std::vector<float> rows(size_t(width_) * height_);
  g.PixelStorei(GL_PACK_ALIGNMENT, 4);
  g.ReadPixels(0, 0, width_, height_, GL_RED, GL_FLOAT, rows.data());
  g.BindFramebuffer(GL_FRAMEBUFFER, 0);
  depth->resize(rows.size());
  for (int y = 0; y < height_; ++y) {
    std::copy_n(&rows[size_t(height_ - 1 - y) * width_], width_, &(*depth)[size_t(y) * width_]);
  }
  const GLenum e = g.GetError();
  if (e != GL_NO_ERROR)
    return Internal("OpenGL error " + std::to_string(e) + " reading a depth map");
  return Status::Ok();
}

void CameraDepthMaps::Bind(GLint unit, GLuint binding) const {
  gl_.ActiveTexture(GLenum(GL_TEXTURE0 + unit));
  gl_.BindTexture(GL_TEXTURE_2D_ARRAY, texture_);
  gl_.BindBufferBase(GL_UNIFORM_BUFFER, binding, block_);
}

}  // namespace fvv
