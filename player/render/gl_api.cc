#include "player/render/gl_api.h"

#include <algorithm>
#include <string>

#include "player/render/shaders.h"

namespace fvv {

Status LoadGlApi(GlProcLoader loader, GlApi* gl) {
#define FVV_GL_LOAD(type, name)                                                      \
  gl->name = reinterpret_cast<type>(loader("gl" #name));                             \
  if (gl->name == nullptr) {                                                         \
    return Unsupported(std::string("OpenGL function gl" #name " is not available")); \
  }
  FVV_GL_FUNCTIONS(FVV_GL_LOAD)
#undef FVV_GL_LOAD
  return Status::Ok();
}

const char* const kSkinningVertexShader = shaders::kSkinningVert;

namespace {

// OK when a shader compiled or a program linked (`status` of `object`);
// otherwise deletes the object and returns its info log in the error. Shaders
// and programs have calls of the same shapes, so one check serves both.
Status CheckBuilt(GLuint object, GLenum status, PFNGLGETSHADERIVPROC get_iv,
                  PFNGLGETSHADERINFOLOGPROC get_log, PFNGLDELETESHADERPROC remove,
                  const std::string& failure) {
  GLint ok = 0;
  get_iv(object, status, &ok);
  if (ok) return Status::Ok();
  char log[2048] = {};
  get_log(object, sizeof(log), nullptr, log);
  remove(object);
  return Internal(failure + log);
}

}  // namespace

StatusOr<GLuint> BuildProgram(const GlApi& g, const char* vertex_source,
                              const char* fragment_source, const std::string& what,
                              const char* feedback) {
  auto compile = [&](GLenum type, const char* src, GLuint* out) -> Status {
    const GLuint s = g.CreateShader(type);
    g.ShaderSource(s, 1, &src, nullptr);
    g.CompileShader(s);
    FVV_RETURN_IF_ERROR(CheckBuilt(s, GL_COMPILE_STATUS, g.GetShaderiv, g.GetShaderInfoLog,
                                   g.DeleteShader, what + ": shader does not compile: "));
    *out = s;
    return Status::Ok();
  };
  GLuint vs = 0, fs = 0;
  FVV_RETURN_IF_ERROR(compile(GL_VERTEX_SHADER, vertex_source, &vs));
  Status s = fragment_source ? compile(GL_FRAGMENT_SHADER, fragment_source, &fs) : Status::Ok();
  if (!s.ok()) {
    g.DeleteShader(vs);
    return s;
  }
  const GLuint program = g.CreateProgram();
  g.AttachShader(program, vs);
  if (fs) g.AttachShader(program, fs);
  if (feedback) g.TransformFeedbackVaryings(program, 1, &feedback, GL_INTERLEAVED_ATTRIBS);
  g.LinkProgram(program);
  g.DeleteShader(vs);
  if (fs) g.DeleteShader(fs);
  FVV_RETURN_IF_ERROR(CheckBuilt(program, GL_LINK_STATUS, g.GetProgramiv, g.GetProgramInfoLog,
                                 g.DeleteProgram, what + ": program does not link: "));
  return program;
}

Status ReadFramebuffer(const GlApi& gl, int width, int height, int channels,
                       std::vector<uint8_t>* pixels) {
  gl.Finish();
  std::vector<uint8_t> rows(size_t(width) * height * channels);
  gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
  gl.ReadPixels(0, 0, width, height,
                channels == 1   ? GL_RED
                : channels == 4 ? GL_RGBA
                                : GL_RGB,
                GL_UNSIGNED_BYTE, rows.data());
  pixels->resize(rows.size());
  const size_t stride = size_t(width) * channels;
  for (int y = 0; y < height; ++y) {  // GL rows run bottom-up
    std::copy_n(rows.data() + size_t(height - 1 - y) * stride, stride,
                pixels->data() + size_t(y) * stride);
  }
  const GLenum e = gl.GetError();
  if (e != GL_NO_ERROR) return Internal("OpenGL error " + std::to_string(e) + " in read-back");
  return Status::Ok();
}

}  // namespace fvv
