#include "player/render/projective_renderer.h"

#include <algorithm>
#include <glm/gtc/type_ptr.hpp>
#include <string>

#include "player/render/shaders.h"

namespace fvv {
namespace {

const char* const kVertexShader = shaders::kProjectiveVert;

// Pass 0 lays down depth and a faint grey coverage (what a fragment no camera
// can texture shows); pass 1 adds one camera's projected colour times weight.
const char* const kAccumulateShader = shaders::kProjectiveAccumulateFrag;

const char* const kResolveVertexShader = shaders::kProjectiveResolveVert;

const char* const kResolveShader = shaders::kProjectiveResolveFrag;

}  // namespace

Status ProjectiveRenderer::CheckGl(const char* where) {
  const GLenum e = gl_.GetError();
  if (e != GL_NO_ERROR) {
    return Internal(std::string("OpenGL error ") + std::to_string(e) + " in Renderer I " + where);
  }
  return Status::Ok();
}

StatusOr<std::unique_ptr<ProjectiveRenderer>> ProjectiveRenderer::Create(
    const GlApi& gl, const std::vector<uint32_t>& triangles, uint32_t vertex_count,
    const std::vector<fvv_camera>& cameras) {
  if (cameras.empty()) return InvalidArgument("Renderer I: no cameras");
  if (vertex_count == 0 || triangles.empty() || triangles.size() % 3) {
    return InvalidArgument("Renderer I: an empty mesh, or indices not in triples");
  }
  for (uint32_t i : triangles) {
    if (i >= vertex_count) return InvalidArgument("Renderer I: a triangle indexes past the mesh");
  }
  for (const fvv_camera& c : cameras) {
    if (c.width == 0 || c.height == 0 || c.width > 16384 || c.height > 16384) {
      return InvalidArgument("Renderer I: camera image size outside 1..16384");
    }
  }
  std::unique_ptr<ProjectiveRenderer> r(new ProjectiveRenderer(gl));
  r->cameras_ = cameras;
  r->vertices_ = vertex_count;
  const GlApi& g = r->gl_;
  StatusOr<GLuint> program = BuildProgram(g, kVertexShader, kAccumulateShader, "Renderer I");
  if (!program.ok()) return program.status();
  r->accumulate_ = *program;
  program = BuildProgram(g, kResolveVertexShader, kResolveShader, "Renderer I resolve");
  if (!program.ok()) return program.status();
  r->resolve_ = *program;

  g.GenVertexArrays(1, &r->vao_);
  g.GenVertexArrays(1, &r->empty_vao_);
  g.BindVertexArray(r->vao_);
  g.GenBuffers(1, &r->positions_);
  g.BindBuffer(GL_ARRAY_BUFFER, r->positions_);
  g.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(vertex_count) * 12, nullptr, GL_DYNAMIC_DRAW);
  g.EnableVertexAttribArray(0);
  g.VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 12, nullptr);
  g.GenBuffers(1, &r->weights_);
  g.BindBuffer(GL_ARRAY_BUFFER, r->weights_);
  g.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(vertex_count) * 4 * GLsizeiptr(cameras.size()), nullptr,
               GL_DYNAMIC_DRAW);
  g.EnableVertexAttribArray(1);
  g.GenBuffers(1, &r->ibo_);
  g.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, r->ibo_);
  g.BufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(triangles.size() * sizeof(uint32_t)),
               triangles.data(), GL_STATIC_DRAW);
  r->index_count_ = GLsizei(triangles.size());
  g.BindVertexArray(0);

  r->images_.resize(cameras.size());
  g.GenTextures(GLsizei(cameras.size()), r->images_.data());
  for (size_t c = 0; c < cameras.size(); ++c) {
    g.BindTexture(GL_TEXTURE_2D, r->images_[c]);
    g.TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, GLsizei(cameras[c].width), GLsizei(cameras[c].height),
                 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
    g.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    g.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    g.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    g.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  }
  FVV_RETURN_IF_ERROR(r->CheckGl("set-up"));
  return r;
}

ProjectiveRenderer::~ProjectiveRenderer() {
  if (framebuffer_) gl_.DeleteFramebuffers(1, &framebuffer_);
  if (accumulation_) gl_.DeleteTextures(1, &accumulation_);
  if (depth_) gl_.DeleteRenderbuffers(1, &depth_);
  if (!images_.empty()) gl_.DeleteTextures(GLsizei(images_.size()), images_.data());
  for (GLuint b : {positions_, weights_, ibo_}) {
    if (b) gl_.DeleteBuffers(1, &b);
  }
  for (GLuint v : {vao_, empty_vao_}) {
    if (v) gl_.DeleteVertexArrays(1, &v);
  }
  if (accumulate_) gl_.DeleteProgram(accumulate_);
  if (resolve_) gl_.DeleteProgram(resolve_);
}

Status ProjectiveRenderer::SetFrame(const std::vector<float>& positions,
                                    const std::vector<float>& weights,
                                    const std::vector<const uint8_t*>& images) {
  const size_t n = vertices_, m = cameras_.size();
  if (positions.size() != n * 3 || weights.size() != n * m || images.size() != m) {
    return InvalidArgument("Renderer I: the frame does not match the mesh and cameras");
  }
  gl_.BindBuffer(GL_ARRAY_BUFFER, positions_);
  gl_.BufferSubData(GL_ARRAY_BUFFER, 0, GLsizeiptr(n * 12), positions.data());
  gl_.BindBuffer(GL_ARRAY_BUFFER, weights_);
  gl_.BufferSubData(GL_ARRAY_BUFFER, 0, GLsizeiptr(n * m * 4), weights.data());
  gl_.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
  used_.assign(m, 0);
  for (size_t c = 0; c < m; ++c) {
    for (size_t v = 0; v < n && !used_[c]; ++v) used_[c] = weights[c * n + v] > 0;
    if (!used_[c]) continue;
    if (!images[c]) return InvalidArgument("Renderer I: a weighted camera has no image");
    // Uploaded top row first: texture t = 0 is image row 0, as the shader's
    // (pixel + 0.5) / size expects.
    gl_.BindTexture(GL_TEXTURE_2D, images_[c]);
    gl_.TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, GLsizei(cameras_[c].width),
                   GLsizei(cameras_[c].height), 0, GL_RGBA, GL_UNSIGNED_BYTE, images[c]);
  }
  has_frame_ = true;
  return CheckGl("frame upload");
}

Status ProjectiveRenderer::PrepareTarget(int width, int height) {
  if (framebuffer_ && width == target_width_ && height == target_height_) return Status::Ok();
  if (!framebuffer_) {
    gl_.GenFramebuffers(1, &framebuffer_);
    gl_.GenTextures(1, &accumulation_);
    gl_.GenRenderbuffers(1, &depth_);
  }
  gl_.BindTexture(GL_TEXTURE_2D, accumulation_);
  gl_.TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, width, height, 0, GL_RGBA, GL_FLOAT, nullptr);
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  gl_.BindRenderbuffer(GL_RENDERBUFFER, depth_);
  gl_.RenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
  gl_.BindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  gl_.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, accumulation_, 0);
  gl_.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_);
  const GLenum status = gl_.CheckFramebufferStatus(GL_FRAMEBUFFER);
  gl_.BindFramebuffer(GL_FRAMEBUFFER, 0);
  if (status != GL_FRAMEBUFFER_COMPLETE) {
    return Unsupported("Renderer I: no floating-point render target (framebuffer status " +
                       std::to_string(status) + ")");
  }
  target_width_ = width;
  target_height_ = height;
  return CheckGl("render target");
}

Status ProjectiveRenderer::Draw(const RenderView& view, int width, int height) {
  if (!has_frame_) return InvalidArgument("Renderer I: Draw before SetFrame");
  FVV_RETURN_IF_ERROR(PrepareTarget(width, height));
  const GlApi& g = gl_;
  g.BindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  g.Viewport(0, 0, width, height);
  g.ClearColor(0, 0, 0, 0);
  g.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  g.UseProgram(accumulate_);
  const glm::mat4 view_proj = view.projection * view.view;
  g.UniformMatrix4fv(g.GetUniformLocation(accumulate_, "u_view_proj"), 1, GL_FALSE,
                     glm::value_ptr(view_proj));
  g.Uniform1i(g.GetUniformLocation(accumulate_, "u_image"), 0);
  g.ActiveTexture(GL_TEXTURE0);
  g.BindVertexArray(vao_);
  g.BindBuffer(GL_ARRAY_BUFFER, weights_);
  g.Enable(GL_DEPTH_TEST);
  g.Enable(GL_BLEND);
  g.BlendFunc(GL_ONE, GL_ONE);
  // Depth and coverage.
  g.DepthFunc(GL_LESS);
  g.DepthMask(GL_TRUE);
  g.Uniform1i(g.GetUniformLocation(accumulate_, "u_pass"), 0);
  g.VertexAttribPointer(1, 1, GL_FLOAT, GL_FALSE, 4, nullptr);
  g.DrawElements(GL_TRIANGLES, index_count_, GL_UNSIGNED_INT, nullptr);
  // One additive pass per camera, on the visible surface only.
  g.DepthFunc(GL_LEQUAL);
  g.DepthMask(GL_FALSE);
  g.Uniform1i(g.GetUniformLocation(accumulate_, "u_pass"), 1);
  for (size_t c = 0; c < cameras_.size(); ++c) {
    if (!used_[c]) continue;
    const fvv_camera& cam = cameras_[c];
    float rotation[9];  // column-major for GL: element (row r, column k) at [k * 3 + r]
    for (int row = 0; row < 3; ++row) {
      for (int k = 0; k < 3; ++k) rotation[k * 3 + row] = float(cam.rotation[row * 3 + k]);
    }
    const float translation[3] = {float(cam.translation[0]), float(cam.translation[1]),
                                  float(cam.translation[2])};
    const float intrinsics[4] = {float(cam.fx), float(cam.fy), float(cam.cx), float(cam.cy)};
    const float distortion[4] = {float(cam.distortion[0]), float(cam.distortion[1]),
                                 float(cam.distortion[2]), float(cam.distortion[3])};
    const float size[2] = {float(cam.width), float(cam.height)};
    g.UniformMatrix3fv(g.GetUniformLocation(accumulate_, "u_rotation"), 1, GL_FALSE, rotation);
    g.Uniform3fv(g.GetUniformLocation(accumulate_, "u_translation"), 1, translation);
    g.Uniform4fv(g.GetUniformLocation(accumulate_, "u_intrinsics"), 1, intrinsics);
    g.Uniform4fv(g.GetUniformLocation(accumulate_, "u_distortion"), 1, distortion);
    g.Uniform1f(g.GetUniformLocation(accumulate_, "u_k3"), float(cam.distortion[4]));
    g.Uniform2fv(g.GetUniformLocation(accumulate_, "u_size"), 1, size);
    g.BindTexture(GL_TEXTURE_2D, images_[c]);
    g.VertexAttribPointer(1, 1, GL_FLOAT, GL_FALSE, 4,
                          reinterpret_cast<const void*>(c * vertices_ * sizeof(float)));
    g.DrawElements(GL_TRIANGLES, index_count_, GL_UNSIGNED_INT, nullptr);
  }
  g.DepthMask(GL_TRUE);
  g.DepthFunc(GL_LESS);
  g.Disable(GL_BLEND);
  g.Disable(GL_DEPTH_TEST);
  // Resolve into the default framebuffer.
  g.BindFramebuffer(GL_FRAMEBUFFER, 0);
  g.Viewport(0, 0, width, height);
  g.UseProgram(resolve_);
  g.Uniform1i(g.GetUniformLocation(resolve_, "u_accum"), 0);
  g.Uniform3fv(g.GetUniformLocation(resolve_, "u_background"), 1, glm::value_ptr(view.background));
  g.BindTexture(GL_TEXTURE_2D, accumulation_);
  g.BindVertexArray(empty_vao_);
  g.DrawArrays(GL_TRIANGLES, 0, 3);
  g.BindVertexArray(0);
  return CheckGl("draw");
}

Status ProjectiveRenderer::ReadRgb(int width, int height, std::vector<uint8_t>* rgb) {
  return ReadFramebuffer(gl_, width, height, 3, rgb);
}

}  // namespace fvv
