#include "player/render/renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <glm/gtc/type_ptr.hpp>
#include <string>

#include "container/geometric_visibility.h"
#include "player/playback/depth_map_triangles.h"
#include "player/render/camera_depth_maps.h"
#include "player/render/shaders.h"

namespace fvv {
namespace {

constexpr int kMaxBones = kMaxSkinBones;
constexpr int kMaxCameras = 64;  // level 4

const char* const kFragmentShader = shaders::kRendererFrag;

}  // namespace

Status Renderer::CheckGl(const char* where) {
  const GLenum e = gl_.GetError();
  if (e != GL_NO_ERROR)
    return Internal(std::string("OpenGL error ") + std::to_string(e) + " in " + where);
  return Status::Ok();
}

StatusOr<std::unique_ptr<Renderer>> Renderer::Create(const GlApi& gl, const fvv_model& model,
                                                     const std::vector<fvv_camera>& cameras,
                                                     uint32_t atlas_width, uint32_t atlas_height) {
  std::vector<glm::vec3> centres;
  for (const fvv_camera& c : cameras) centres.emplace_back(c.centre[0], c.centre[1], c.centre[2]);
  if (model.bone_count > kMaxBones) {
    return Unsupported("renderer: " + std::to_string(model.bone_count) + " bones (at most 256)");
  }
  if (centres.empty() || centres.size() > kMaxCameras) {
    return Unsupported("renderer: " + std::to_string(centres.size()) + " cameras (1..64)");
  }
  std::unique_ptr<Renderer> r(new Renderer(gl));
  r->cameras_ = static_cast<uint32_t>(centres.size());
  r->camera_list_ = cameras;
  r->camera_centres_ = centres;
  r->width_ = atlas_width;
  r->height_ = atlas_height;
  r->bones_ = model.bone_count;
  const GlApi& g = r->gl_;

  // One program per visibility source: a software renderer pays for a branch
  // it never takes (the depth lookups cost a masked stream a third of its
  // draw on OSMesa).
  const std::string source = kFragmentShader;
  const size_t body = source.find('\n') + 1;  // after #version
  const std::string depth_source =
      source.substr(0, body) + "#define FVV_DEPTH_VISIBILITY 1\n" + source.substr(body);
  StatusOr<GLuint> program = BuildProgram(g, kSkinningVertexShader, kFragmentShader, "renderer");
  if (!program.ok()) return program.status();
  r->program_ = *program;
  program = BuildProgram(g, kSkinningVertexShader, depth_source.c_str(), "renderer (depth maps)");
  if (!program.ok()) return program.status();
  r->depth_program_ = *program;

  // Interleaved vertices: normal 3, uv 2, weights 4 floats; joints. The
  // positions have a buffer of their own: a frame's surface replaces them.
  struct Vertex {
    float n[3], uv[2], w[4];
    uint32_t j[4];
  };
  std::vector<Vertex> vertices(model.vertex_count);
  for (uint32_t v = 0; v < model.vertex_count; ++v) {
    for (int k = 0; k < 3; ++k) vertices[v].n[k] = model.normals[3 * v + k];
    for (int k = 0; k < 2; ++k) vertices[v].uv[k] = model.uvs[2 * v + k];
    for (int k = 0; k < 4; ++k) {
      vertices[v].w[k] = model.weights[4 * v + k];
      vertices[v].j[k] = model.joints[4 * v + k] < model.bone_count ? model.joints[4 * v + k] : 0;
    }
  }
  g.GenVertexArrays(1, &r->vao_);
  g.BindVertexArray(r->vao_);
  g.GenBuffers(1, &r->vbo_);
  g.BindBuffer(GL_ARRAY_BUFFER, r->vbo_);
  g.BufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vertices.size() * sizeof(Vertex)),
               vertices.data(), GL_STATIC_DRAW);
  const GLsizei stride = sizeof(Vertex);
  auto offset = [](size_t o) { return reinterpret_cast<const void*>(o); };
  g.EnableVertexAttribArray(1);
  g.VertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride, offset(offsetof(Vertex, n)));
  g.EnableVertexAttribArray(2);
  g.VertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, stride, offset(offsetof(Vertex, uv)));
  g.EnableVertexAttribArray(3);
  g.VertexAttribIPointer(3, 4, GL_UNSIGNED_INT, stride, offset(offsetof(Vertex, j)));
  g.EnableVertexAttribArray(4);
  g.VertexAttribPointer(4, 4, GL_FLOAT, GL_FALSE, stride, offset(offsetof(Vertex, w)));
  r->model_positions_.assign(model.positions, model.positions + size_t{model.vertex_count} * 3);
  g.GenBuffers(1, &r->positions_vbo_);
  g.BindBuffer(GL_ARRAY_BUFFER, r->positions_vbo_);
  g.BufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(model.vertex_count * 3 * sizeof(float)),
               model.positions, GL_DYNAMIC_DRAW);
  g.EnableVertexAttribArray(0);
  g.VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 3 * sizeof(float), nullptr);
  g.GenBuffers(1, &r->ibo_);
  g.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, r->ibo_);
  g.BufferData(GL_ELEMENT_ARRAY_BUFFER,
               static_cast<GLsizeiptr>(model.triangle_count * 3 * sizeof(uint32_t)),
               model.triangles, GL_STATIC_DRAW);
  r->index_count_ = static_cast<GLsizei>(model.triangle_count * 3);
  r->vertex_count_ = model.vertex_count;
  g.BindVertexArray(0);
  r->model_triangles_.assign(model.triangles, model.triangles + size_t{model.triangle_count} * 3);

  g.GenBuffers(1, &r->bones_ubo_);
  g.BindBuffer(GL_UNIFORM_BUFFER, r->bones_ubo_);
  g.BufferData(GL_UNIFORM_BUFFER, kMaxBones * 64, nullptr, GL_DYNAMIC_DRAW);
  g.UniformBlockBinding(r->program_, g.GetUniformBlockIndex(r->program_, "Bones"), 0);
  g.UniformBlockBinding(r->depth_program_, g.GetUniformBlockIndex(r->depth_program_, "Bones"), 0);
  g.UniformBlockBinding(r->depth_program_,
                        g.GetUniformBlockIndex(r->depth_program_, "DepthCameras"), 1);

  auto make_array = [&](GLuint* tex, GLint internal, GLenum format) {
    g.GenTextures(1, tex);
    g.BindTexture(GL_TEXTURE_2D_ARRAY, *tex);
    g.TexImage3D(GL_TEXTURE_2D_ARRAY, 0, internal, static_cast<GLsizei>(atlas_width),
                 static_cast<GLsizei>(atlas_height), static_cast<GLsizei>(r->cameras_), 0, format,
                 GL_UNSIGNED_BYTE, nullptr);
    g.TexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    g.TexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    g.TexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    g.TexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  };
  make_array(&r->textures_, GL_RGB8, GL_RGB);
  make_array(&r->masks_, GL_R8, GL_RED);
  FVV_RETURN_IF_ERROR(r->CheckGl("renderer set-up"));
  return r;
}

Renderer::~Renderer() {
  if (textures_) gl_.DeleteTextures(1, &textures_);
  if (masks_) gl_.DeleteTextures(1, &masks_);
  if (bones_ubo_) gl_.DeleteBuffers(1, &bones_ubo_);
  if (vbo_) gl_.DeleteBuffers(1, &vbo_);
  if (positions_vbo_) gl_.DeleteBuffers(1, &positions_vbo_);
  if (ibo_) gl_.DeleteBuffers(1, &ibo_);
  if (depth_map_ibo_) gl_.DeleteBuffers(1, &depth_map_ibo_);
  if (vao_) gl_.DeleteVertexArrays(1, &vao_);
  if (program_) gl_.DeleteProgram(program_);
  if (depth_program_) gl_.DeleteProgram(depth_program_);
}

Status Renderer::SetFrame(const fvv_frame& frame) {
  if (frame.format != FVV_FORMAT_RGB8) return InvalidArgument("renderer: frames must be RGB8");
  if (frame.camera_count != cameras_ || frame.width != width_ || frame.height != height_ ||
      frame.bone_count != bones_) {
    return InvalidArgument("renderer: the frame does not match the stream it was set up for");
  }
  gl_.BindBuffer(GL_UNIFORM_BUFFER, bones_ubo_);
  gl_.BufferSubData(GL_UNIFORM_BUFFER, 0, static_cast<GLsizeiptr>(bones_ * 64), frame.bone_skin);
  // The frame's own surface (format version 12), or the model's again.
  const float* positions = frame.surface ? frame.surface : model_positions_.data();
  if (frame.surface || positions_are_surface_) {
    gl_.BindBuffer(GL_ARRAY_BUFFER, positions_vbo_);
    gl_.BufferSubData(GL_ARRAY_BUFFER, 0,
                      static_cast<GLsizeiptr>(vertex_count_ * 3 * sizeof(float)), positions);
    gl_.BindBuffer(GL_ARRAY_BUFFER, 0);
    positions_are_surface_ = frame.surface != nullptr;
  }
  gl_.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
  has_masks_ = false;
  bool any = false;
  present_.assign(cameras_, 0);
  for (uint32_t c = 0; c < cameras_; ++c) {
    present_[c] = frame.views[c].pixels != nullptr;
    if (present_[c] && !any) has_masks_ = frame.views[c].mask != nullptr;
    any = any || present_[c];
  }
  if (!any) return InvalidArgument("renderer: the frame holds no camera's texture");
  const size_t texels = size_t{width_} * height_;
  mask_scratch_.resize(texels);
  for (uint32_t c = 0; c < cameras_; ++c) {
    if (!present_[c]) continue;  // left out of the decode (fvv_decode_budget.camera_mask)
    gl_.BindTexture(GL_TEXTURE_2D_ARRAY, textures_);
    gl_.TexSubImage3D(GL_TEXTURE_2D_ARRAY, 0, 0, 0, static_cast<GLint>(c),
                      static_cast<GLsizei>(width_), static_cast<GLsizei>(height_), 1, GL_RGB,
                      GL_UNSIGNED_BYTE, frame.views[c].pixels);
    if (has_masks_) {
      for (size_t i = 0; i < texels; ++i) mask_scratch_[i] = frame.views[c].mask[i] ? 255 : 0;
      gl_.BindTexture(GL_TEXTURE_2D_ARRAY, masks_);
      gl_.TexSubImage3D(GL_TEXTURE_2D_ARRAY, 0, 0, 0, static_cast<GLint>(c),
                        static_cast<GLsizei>(width_), static_cast<GLsizei>(height_), 1, GL_RED,
                        GL_UNSIGNED_BYTE, mask_scratch_.data());
    }
  }
  actor_centre_ = glm::vec3(frame.bone_world[12], frame.bone_world[13], frame.bone_world[14]);
  depth_rendered_ = 0;
  has_frame_ = true;
  return CheckGl("frame upload");
}

Status Renderer::Draw(const RenderView& view, int width, int height) {
  if (!has_frame_) return InvalidArgument("renderer: Draw before SetFrame");
  // Cameras far round the actor from the viewer weigh next to nothing (at 110
  // degrees off, under 0.3 % of one 22 degrees off with the default exponent)
  // but would cost the fragment shader as much as the others: of the cameras
  // whose textures are here, the closest (at least 3, at most
  // kMaxViewCameras) within 110 degrees.
  std::vector<glm::vec3> here;
  std::vector<GLint> view_cameras, picked;
  for (uint32_t c = 0; c < cameras_ && c < 64; ++c) {
    if (!present_[c]) continue;
    here.push_back(camera_centres_[c]);
    picked.push_back(GLint(c));
  }
  const uint64_t near = ViewCameras(here, view.eye, actor_centre_, 110.0f, 3);
  uint64_t active_bits = 0;
  for (size_t k = 0; k < picked.size(); ++k) {
    if (!((near >> k) & 1)) continue;
    view_cameras.push_back(picked[k]);
    active_bits |= uint64_t{1} << picked[k];
  }
  if (!has_masks_) FVV_RETURN_IF_ERROR(RenderDepthMaps(active_bits));
  gl_.Viewport(0, 0, width, height);
  // Alpha 0 where nothing is drawn: ReadCoverage tells the actor's pixels.
  gl_.ClearColor(view.background.r, view.background.g, view.background.b, 0.0f);
  gl_.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  gl_.Enable(GL_DEPTH_TEST);
  // The body model is closed and wound counter-clockwise: its back faces are
  // hidden anyway, and a software rasteriser would shade them first.
  gl_.Enable(GL_CULL_FACE);
  const GLuint program = has_masks_ ? program_ : depth_program_;
  gl_.UseProgram(program);
  const glm::mat4 view_proj = view.projection * view.view;
  gl_.Uniform1i(gl_.GetUniformLocation(program, "u_skinned"), 1);
  gl_.UniformMatrix4fv(gl_.GetUniformLocation(program, "u_view_proj"), 1, GL_FALSE,
                       glm::value_ptr(view_proj));
  gl_.Uniform3fv(gl_.GetUniformLocation(program, "u_cameras"), static_cast<GLsizei>(cameras_),
                 glm::value_ptr(camera_centres_[0]));
  gl_.Uniform1i(gl_.GetUniformLocation(program, "u_view_camera_count"),
                static_cast<GLint>(view_cameras.size()));
  gl_.Uniform1iv(gl_.GetUniformLocation(program, "u_view_cameras"),
                 static_cast<GLsizei>(view_cameras.size()), view_cameras.data());
  gl_.Uniform3fv(gl_.GetUniformLocation(program, "u_eye"), 1, glm::value_ptr(view.eye));
  gl_.Uniform1f(gl_.GetUniformLocation(program, "u_exponent"), view.exponent);
  gl_.Uniform1f(gl_.GetUniformLocation(program, "u_angle_epsilon"),
                float(geometric_visibility::kAngleEpsilon));
  gl_.Uniform1f(gl_.GetUniformLocation(program, "u_facing_exponent"), view.facing_exponent);
  gl_.Uniform1i(gl_.GetUniformLocation(program, "u_textures"), 0);
  gl_.Uniform1i(gl_.GetUniformLocation(program, "u_masks"), 1);
  gl_.Uniform1i(gl_.GetUniformLocation(program, "u_depth"), 2);
  namespace gv = geometric_visibility;
  gl_.Uniform4fv(gl_.GetUniformLocation(program, "u_visibility_rule"), 1,
                 glm::value_ptr(glm::vec4(gv::kDepthTolerance, gv::kSlopeTexels, gv::kMinFacing,
                                          gv::kFullFacing)));
  gl_.ActiveTexture(GL_TEXTURE0);
  gl_.BindTexture(GL_TEXTURE_2D_ARRAY, textures_);
  gl_.ActiveTexture(GL_TEXTURE1);
  gl_.BindTexture(GL_TEXTURE_2D_ARRAY, masks_);
  gl_.BindBufferBase(GL_UNIFORM_BUFFER, 0, bones_ubo_);
  if (!has_masks_) depth_maps_->Bind(2, 1);
  gl_.BindVertexArray(vao_);
  gl_.DrawElements(GL_TRIANGLES, index_count_, GL_UNSIGNED_INT, nullptr);
  gl_.Disable(GL_CULL_FACE);
  gl_.BindVertexArray(0);
  gl_.ActiveTexture(GL_TEXTURE0);
  return CheckGl("draw");
}

Status Renderer::RenderDepthMaps(uint64_t cameras) {
  const uint64_t needed = cameras & ~depth_rendered_;
  if (!needed) return Status::Ok();
  if (!depth_maps_) {
    FVV_ASSIGN_OR_RETURN(depth_maps_, CameraDepthMaps::Create(gl_, camera_list_));
    // The simplified body they draw, made now: a stream with masks never needs it.
    const std::vector<uint32_t> triangles =
        DepthMapTriangles(model_positions_.data(), vertex_count_, model_triangles_.data(),
                          static_cast<uint32_t>(model_triangles_.size() / 3));
    gl_.BindVertexArray(0);  // the index buffer binding is a vertex array's state
    gl_.GenBuffers(1, &depth_map_ibo_);
    gl_.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, depth_map_ibo_);
    gl_.BufferData(GL_ELEMENT_ARRAY_BUFFER,
                   static_cast<GLsizeiptr>(triangles.size() * sizeof(uint32_t)), triangles.data(),
                   GL_STATIC_DRAW);
    gl_.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, 0);
    depth_map_index_count_ = static_cast<GLsizei>(triangles.size());
    model_triangles_ = {};
  }
  GLint framebuffer = 0;
  gl_.GetIntegerv(GL_FRAMEBUFFER_BINDING, &framebuffer);
  const auto t0 = std::chrono::steady_clock::now();
  FVV_RETURN_IF_ERROR(depth_maps_->Render(vao_, GLsizei(vertex_count_), depth_map_ibo_,
                                          depth_map_index_count_, bones_ubo_, needed));
  if (measure_depth_maps_) {
    gl_.Finish();
    depth_map_ms_ +=
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  }
  for (uint64_t b = needed; b; b &= b - 1) ++depth_map_layers_;
  gl_.BindFramebuffer(GL_FRAMEBUFFER, GLuint(framebuffer));
  depth_rendered_ |= needed;
  return Status::Ok();
}

Status Renderer::ReadCoverage(int width, int height, std::vector<uint8_t>* coverage) {
  std::vector<uint8_t> rgba;
  FVV_RETURN_IF_ERROR(ReadFramebuffer(gl_, width, height, 4, &rgba));
  coverage->resize(rgba.size() / 4);
  for (size_t i = 0; i < coverage->size(); ++i) (*coverage)[i] = rgba[4 * i + 3] ? 255 : 0;
  return Status::Ok();
}

Status Renderer::ReadRgb(int width, int height, std::vector<uint8_t>* rgb) {
  return ReadFramebuffer(gl_, width, height, 3, rgb);
}

std::vector<fvv_camera> DecoderCameras(const fvv_decoder* decoder) {
  fvv_stream_info info;
  std::vector<fvv_camera> cameras;
  if (fvv_decoder_get_info(decoder, &info) != FVV_OK) return cameras;
  for (uint32_t c = 0; c < info.camera_count; ++c) {
    fvv_camera cam;
    if (fvv_decoder_get_camera(decoder, c, &cam) != FVV_OK) return {};
    cameras.push_back(cam);
  }
  return cameras;
}

void CameraViewProjection(const fvv_camera& c, float near_m, float far_m, glm::mat4* view,
                          glm::mat4* projection) {
  // World -> OpenCV camera (x right, y down, z forward), then flip y and z for GL.
  // OpenCV puts pixel centres at integer coordinates, GL at half-integers: hence
  // cx + 0.5 and cy + 0.5 below.
  glm::mat4 rt(1.0f);
  for (int r = 0; r < 3; ++r) {
    for (int k = 0; k < 3; ++k) rt[k][r] = static_cast<float>(c.rotation[3 * r + k]);
    rt[3][r] = static_cast<float>(c.translation[r]);
  }
  glm::mat4 flip(1.0f);
  flip[1][1] = -1.0f;
  flip[2][2] = -1.0f;
  *view = flip * rt;
  const float w = static_cast<float>(c.width), h = static_cast<float>(c.height);
  glm::mat4 p(0.0f);
  p[0][0] = 2.0f * static_cast<float>(c.fx) / w;
  p[1][1] = 2.0f * static_cast<float>(c.fy) / h;
  p[2][0] = 1.0f - 2.0f * static_cast<float>(c.cx + 0.5) / w;
  p[2][1] = 2.0f * static_cast<float>(c.cy + 0.5) / h - 1.0f;
  p[2][2] = -(far_m + near_m) / (far_m - near_m);
  p[2][3] = -1.0f;
  p[3][2] = -2.0f * far_m * near_m / (far_m - near_m);
  *projection = p;
}

}  // namespace fvv
