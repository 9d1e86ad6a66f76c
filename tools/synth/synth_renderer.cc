#include "tools/synth/synth_renderer.h"

#include <Eigen/Geometry>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>

#include "player/decoder/public_camera.h"
#include "player/render/renderer.h"
#include "tools/synth/shaders.h"

namespace fvv {
namespace {

// Mode 0: the actor, textured; 1: the studio, procedural; 2: silhouette.
const char* const kFragmentShader = shaders::kSynthFrag;

}  // namespace

StatusOr<std::unique_ptr<SynthRenderer>> SynthRenderer::Create(const GlApi& gl,
                                                               const ActorMesh& mesh,
                                                               size_t bone_count, bool clutter) {
  if (bone_count == 0 || bone_count > kMaxBones) {
    return Unsupported("synth: actor has " + std::to_string(bone_count) + " bones (1..256)");
  }
  if (mesh.texture.channels != 3 || mesh.texture.width == 0) {
    return InvalidArgument("synth: actor texture must be a non-empty RGB image");
  }
  std::unique_ptr<SynthRenderer> r(new SynthRenderer(gl));
  const GlApi& g = r->gl_;
  StatusOr<GLuint> program =
      BuildProgram(g, kSkinningVertexShader, kFragmentShader, "synth renderer");
  if (!program.ok()) return program.status();
  r->program_ = *program;
  r->u_view_proj_ = g.GetUniformLocation(r->program_, "u_view_proj");
  r->u_skinned_ = g.GetUniformLocation(r->program_, "u_skinned");
  r->u_mode_ = g.GetUniformLocation(r->program_, "u_mode");
  r->u_shadow_ = g.GetUniformLocation(r->program_, "u_shadow");
  r->u_shadow_on_ = g.GetUniformLocation(r->program_, "u_shadow_on");
  r->u_unlit_ = g.GetUniformLocation(r->program_, "u_unlit");

  auto buffer = [&](GLenum target, const void* data, size_t bytes) {
    GLuint b = 0;
    g.GenBuffers(1, &b);
    g.BindBuffer(target, b);
    g.BufferData(target, static_cast<GLsizeiptr>(bytes), data, GL_STATIC_DRAW);
    r->buffers_.push_back(b);
  };
  auto attrib = [&](GLuint index, int size, const void* data, size_t bytes) {
    buffer(GL_ARRAY_BUFFER, data, bytes);
    g.EnableVertexAttribArray(index);
    g.VertexAttribPointer(index, size, GL_FLOAT, GL_FALSE, 0, nullptr);
  };
  // The actor: one buffer per attribute (Eigen vectors are tightly packed floats).
  const size_t n = mesh.positions.size();
  g.GenVertexArrays(1, &r->actor_vao_);
  g.BindVertexArray(r->actor_vao_);
  attrib(0, 3, mesh.positions.data(), n * 12);
  r->actor_positions_ = r->buffers_.back();
  r->actor_vertices_ = n;
  attrib(1, 3, mesh.normals.data(), n * 12);
  attrib(2, 2, mesh.uvs.data(), n * 8);
  std::vector<uint32_t> joints(n * 4);
  for (size_t v = 0; v < n; ++v) {
    for (int k = 0; k < 4; ++k)
      joints[4 * v + k] = mesh.joints[v][k] < bone_count ? mesh.joints[v][k] : 0;
  }
  buffer(GL_ARRAY_BUFFER, joints.data(), joints.size() * 4);
  g.EnableVertexAttribArray(3);
  g.VertexAttribIPointer(3, 4, GL_UNSIGNED_INT, 0, nullptr);
  attrib(4, 4, mesh.weights.data(), n * 16);
  buffer(GL_ELEMENT_ARRAY_BUFFER, mesh.indices.data(), mesh.indices.size() * 4);
  r->actor_indices_ = static_cast<GLsizei>(mesh.indices.size());

  // The studio: a 12 m x 12 m floor and four 4.5 m walls (normals face inwards).
  // Per vertex a prop number (the uv attribute's u): 0 for the room.
  std::vector<float> sp, sn, sprop;
  std::vector<uint32_t> si;
  float prop = 0;
  auto quad = [&](const Eigen::Vector3f& o, const Eigen::Vector3f& a, const Eigen::Vector3f& b) {
    const Eigen::Vector3f normal = a.cross(b).normalized();
    const uint32_t base = static_cast<uint32_t>(sp.size() / 3);
    for (const Eigen::Vector3f& p :
         {o, Eigen::Vector3f(o + a), Eigen::Vector3f(o + a + b), Eigen::Vector3f(o + b)}) {
      sp.insert(sp.end(), {p.x(), p.y(), p.z()});
      sn.insert(sn.end(), {normal.x(), normal.y(), normal.z()});
      sprop.insert(sprop.end(), {prop, 0.0f});
    }
    si.insert(si.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
  };
  const float h = 6.0f, top = 4.5f;
  quad({-h, 0, -h}, {0, 0, 2 * h}, {2 * h, 0, 0});    // floor, normal +y
  quad({-h, 0, -h}, {2 * h, 0, 0}, {0, top, 0});      // back wall, normal +z
  quad({h, 0, h}, {-2 * h, 0, 0}, {0, top, 0});       // front wall, normal -z
  quad({-h, 0, h}, {0, 0, -2 * h}, {0, top, 0});      // left wall, normal +x
  quad({h, 0, -h}, {0, 0, 2 * h}, {0, top, 0});       // right wall, normal -x
  quad({-h, top, -h}, {2 * h, 0, 0}, {0, 0, 2 * h});  // ceiling, normal -y
  if (clutter) {
    // Boxes standing on the floor around the capture volume, between it and
    // the ring of cameras or behind it: a desk, crates, a cabinet, two stands.
    // (centre x, z, half extents x, y, z; y from the floor)
    const float boxes[][5] = {{-2.2f, -1.9f, 0.7f, 0.38f, 0.35f}, {2.3f, -1.2f, 0.3f, 0.3f, 0.3f},
                              {1.9f, 2.3f, 0.45f, 0.9f, 0.25f},   {-2.6f, 1.4f, 0.25f, 0.22f, 0.4f},
                              {0.4f, -2.7f, 0.06f, 0.85f, 0.06f}, {-1.2f, 2.6f, 0.06f, 0.7f, 0.06f},
                              {2.8f, 0.6f, 0.35f, 0.55f, 0.35f}};
    for (const auto& bx : boxes) {
      prop += 1;
      const Eigen::Vector3f lo(bx[0] - bx[2], 0, bx[1] - bx[4]);
      const Eigen::Vector3f dx(2 * bx[2], 0, 0), dy(0, 2 * bx[3], 0), dz(0, 0, 2 * bx[4]);
      quad(lo + dy, dz, dx);  // top, normal +y
      quad(lo, dx, dy);       // normal -z
      quad(lo + dz, dy, dx);  // normal +z
      quad(lo, dy, dz);       // normal -x
      quad(lo + dx, dz, dy);  // normal +x
    }
  }
  g.GenVertexArrays(1, &r->studio_vao_);
  g.BindVertexArray(r->studio_vao_);
  attrib(0, 3, sp.data(), sp.size() * 4);
  attrib(1, 3, sn.data(), sn.size() * 4);
  attrib(2, 2, sprop.data(), sprop.size() * 4);
  buffer(GL_ELEMENT_ARRAY_BUFFER, si.data(), si.size() * 4);
  r->studio_indices_ = static_cast<GLsizei>(si.size());
  g.BindVertexArray(0);

  g.GenBuffers(1, &r->bones_ubo_);
  g.BindBuffer(GL_UNIFORM_BUFFER, r->bones_ubo_);
  g.BufferData(GL_UNIFORM_BUFFER, kMaxBones * 64, nullptr, GL_DYNAMIC_DRAW);
  g.UniformBlockBinding(r->program_, g.GetUniformBlockIndex(r->program_, "Bones"), 0);

  g.GenTextures(1, &r->texture_);
  g.BindTexture(GL_TEXTURE_2D_ARRAY, r->texture_);
  g.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
  g.TexImage3D(GL_TEXTURE_2D_ARRAY, 0, GL_RGB8, static_cast<GLsizei>(mesh.texture.width),
               static_cast<GLsizei>(mesh.texture.height), 1, 0, GL_RGB, GL_UNSIGNED_BYTE,
               mesh.texture.pixels.data());
  g.TexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  g.TexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  g.TexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_S, GL_REPEAT);
  g.TexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_T, GL_REPEAT);
  const GLenum e = g.GetError();
  if (e != GL_NO_ERROR) return Internal("synth renderer set-up: OpenGL error " + std::to_string(e));
  return r;
}

SynthRenderer::~SynthRenderer() {
  if (texture_) gl_.DeleteTextures(1, &texture_);
  if (bones_ubo_) gl_.DeleteBuffers(1, &bones_ubo_);
  if (!buffers_.empty()) gl_.DeleteBuffers(static_cast<GLsizei>(buffers_.size()), buffers_.data());
  if (actor_vao_) gl_.DeleteVertexArrays(1, &actor_vao_);
  if (studio_vao_) gl_.DeleteVertexArrays(1, &studio_vao_);
  if (program_) gl_.DeleteProgram(program_);
}

Status SynthRenderer::SetCamera(const Camera& camera) {
  glm::mat4 view, projection;
  CameraViewProjection(PublicCamera(camera), 0.05f, 40.0f, &view, &projection);
  const glm::mat4 vp = projection * view;
  gl_.Viewport(0, 0, static_cast<GLsizei>(camera.width), static_cast<GLsizei>(camera.height));
  gl_.Enable(GL_DEPTH_TEST);
  gl_.UseProgram(program_);
  gl_.UniformMatrix4fv(u_view_proj_, 1, GL_FALSE, glm::value_ptr(vp));
  gl_.ActiveTexture(GL_TEXTURE0);
  gl_.BindTexture(GL_TEXTURE_2D_ARRAY, texture_);
  gl_.Uniform1i(gl_.GetUniformLocation(program_, "u_texture"), 0);
  return Status::Ok();
}

void SynthRenderer::DrawActor(const std::vector<Eigen::Matrix4f>& skinning, int mode) {
  std::vector<float> bones(kMaxBones * 16, 0.0f);
  for (size_t b = 0; b < skinning.size() && b < kMaxBones; ++b) {
    std::copy_n(skinning[b].data(), 16, bones.data() + 16 * b);  // Eigen is column-major, as GL
  }
  gl_.BindBuffer(GL_UNIFORM_BUFFER, bones_ubo_);
  gl_.BufferSubData(GL_UNIFORM_BUFFER, 0, static_cast<GLsizeiptr>(bones.size() * 4), bones.data());
  gl_.BindBufferBase(GL_UNIFORM_BUFFER, 0, bones_ubo_);
  gl_.Uniform1i(u_skinned_, 1);
  gl_.Uniform1i(u_mode_, mode);
  gl_.BindVertexArray(actor_vao_);
  gl_.DrawElements(GL_TRIANGLES, actor_indices_, GL_UNSIGNED_INT, nullptr);
  gl_.BindVertexArray(0);
}

Status SynthRenderer::DrawScene(const Camera& camera, const std::vector<Eigen::Matrix4f>* skinning,
                                const Eigen::Vector3d& root) {
  FVV_RETURN_IF_ERROR(SetCamera(camera));
  gl_.ClearColor(0, 0, 0, 1);
  gl_.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  const float shadow[3] = {float(root.x()), 0.0f, float(root.z())};
  gl_.Uniform3fv(u_shadow_, 1, shadow);
  gl_.Uniform1f(u_shadow_on_, skinning ? 1.0f : 0.0f);
  gl_.Uniform1f(u_unlit_, unlit_ ? 1.0f : 0.0f);
  gl_.Uniform1i(u_skinned_, 0);
  gl_.Uniform1i(u_mode_, 1);
  gl_.BindVertexArray(studio_vao_);
  gl_.DrawElements(GL_TRIANGLES, studio_indices_, GL_UNSIGNED_INT, nullptr);
  gl_.BindVertexArray(0);
  if (skinning) DrawActor(*skinning, 0);
  const GLenum e = gl_.GetError();
  if (e != GL_NO_ERROR) return Internal("synth: OpenGL error " + std::to_string(e) + " drawing");
  return Status::Ok();
}

Status SynthRenderer::DrawActorOver(const Camera& camera,
                                    const std::vector<Eigen::Matrix4f>& skinning) {
  FVV_RETURN_IF_ERROR(SetCamera(camera));
  gl_.Uniform1f(u_unlit_, unlit_ ? 1.0f : 0.0f);
  DrawActor(skinning, 0);
  const GLenum e = gl_.GetError();
  if (e != GL_NO_ERROR) return Internal("synth: OpenGL error " + std::to_string(e) + " drawing");
  return Status::Ok();
}

Status SynthRenderer::DrawSilhouette(const Camera& camera,
                                     const std::vector<Eigen::Matrix4f>& skinning) {
  FVV_RETURN_IF_ERROR(SetCamera(camera));
  gl_.ClearColor(0, 0, 0, 1);
  gl_.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  DrawActor(skinning, 2);
  const GLenum e = gl_.GetError();
  if (e != GL_NO_ERROR) return Internal("synth: OpenGL error " + std::to_string(e) + " drawing");
  return Status::Ok();
}

void SynthRenderer::SetActorPositions(const std::vector<Eigen::Vector3f>& positions) {
  const size_t n = std::min(positions.size(), actor_vertices_);
  gl_.BindBuffer(GL_ARRAY_BUFFER, actor_positions_);
  gl_.BufferSubData(GL_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(n * 12), positions.data());
  gl_.BindBuffer(GL_ARRAY_BUFFER, 0);
}

StatusOr<Image> SynthRenderer::Read(const Camera& camera, int channels) {
  Image image;
  image.width = camera.width;
  image.height = camera.height;
  image.channels = channels;
  FVV_RETURN_IF_ERROR(
      ReadFramebuffer(gl_, int(camera.width), int(camera.height), channels, &image.pixels));
  return image;
}

}  // namespace fvv
