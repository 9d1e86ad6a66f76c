// The OpenGL 3.3 core functions the renderers use, loaded through whatever the
// context provides (OSMesaGetProcAddress headless, glfwGetProcAddress windowed),
// so the same renderer code runs on both without linking two GL libraries.
#ifndef FVV_PLAYER_RENDER_GL_API_H_
#define FVV_PLAYER_RENDER_GL_API_H_

#include <GL/glcorearb.h>

#include <string>
#include <vector>

#include "codec/base/status.h"

namespace fvv {

#define FVV_GL_FUNCTIONS(X)                                        \
  X(PFNGLACTIVETEXTUREPROC, ActiveTexture)                         \
  X(PFNGLATTACHSHADERPROC, AttachShader)                           \
  X(PFNGLBINDBUFFERPROC, BindBuffer)                               \
  X(PFNGLBINDBUFFERBASEPROC, BindBufferBase)                       \
  X(PFNGLBINDFRAMEBUFFERPROC, BindFramebuffer)                     \
  X(PFNGLBINDRENDERBUFFERPROC, BindRenderbuffer)                   \
  X(PFNGLBINDTEXTUREPROC, BindTexture)                             \
  X(PFNGLBEGINTRANSFORMFEEDBACKPROC, BeginTransformFeedback)       \
  X(PFNGLBINDVERTEXARRAYPROC, BindVertexArray)                     \
  X(PFNGLBLENDFUNCPROC, BlendFunc)                                 \
  X(PFNGLBUFFERDATAPROC, BufferData)                               \
  X(PFNGLBUFFERSUBDATAPROC, BufferSubData)                         \
  X(PFNGLCHECKFRAMEBUFFERSTATUSPROC, CheckFramebufferStatus)       \
  X(PFNGLCLEARPROC, Clear)                                         \
  X(PFNGLCLEARCOLORPROC, ClearColor)                               \
  X(PFNGLCOLORMASKPROC, ColorMask)                                 \
  X(PFNGLCOMPILESHADERPROC, CompileShader)                         \
  X(PFNGLCREATEPROGRAMPROC, CreateProgram)                         \
  X(PFNGLCREATESHADERPROC, CreateShader)                           \
  X(PFNGLDELETEBUFFERSPROC, DeleteBuffers)                         \
  X(PFNGLDELETEFRAMEBUFFERSPROC, DeleteFramebuffers)               \
  X(PFNGLDELETEPROGRAMPROC, DeleteProgram)                         \
  X(PFNGLDELETERENDERBUFFERSPROC, DeleteRenderbuffers)             \
  X(PFNGLDELETESHADERPROC, DeleteShader)                           \
  X(PFNGLDELETETEXTURESPROC, DeleteTextures)                       \
  X(PFNGLDELETEVERTEXARRAYSPROC, DeleteVertexArrays)               \
  X(PFNGLDEPTHFUNCPROC, DepthFunc)                                 \
  X(PFNGLDEPTHMASKPROC, DepthMask)                                 \
  X(PFNGLDISABLEPROC, Disable)                                     \
  X(PFNGLDRAWARRAYSPROC, DrawArrays)                               \
  X(PFNGLDRAWELEMENTSPROC, DrawElements)                           \
  X(PFNGLENABLEPROC, Enable)                                       \
  X(PFNGLENABLEVERTEXATTRIBARRAYPROC, EnableVertexAttribArray)     \
  X(PFNGLENDTRANSFORMFEEDBACKPROC, EndTransformFeedback)           \
  X(PFNGLFINISHPROC, Finish)                                       \
  X(PFNGLFRAMEBUFFERRENDERBUFFERPROC, FramebufferRenderbuffer)     \
  X(PFNGLFRAMEBUFFERTEXTURE2DPROC, FramebufferTexture2D)           \
  X(PFNGLFRAMEBUFFERTEXTURELAYERPROC, FramebufferTextureLayer)     \
  X(PFNGLGENBUFFERSPROC, GenBuffers)                               \
  X(PFNGLGENFRAMEBUFFERSPROC, GenFramebuffers)                     \
  X(PFNGLGENRENDERBUFFERSPROC, GenRenderbuffers)                   \
  X(PFNGLGENTEXTURESPROC, GenTextures)                             \
  X(PFNGLGENVERTEXARRAYSPROC, GenVertexArrays)                     \
  X(PFNGLGETERRORPROC, GetError)                                   \
  X(PFNGLGETINTEGERVPROC, GetIntegerv)                             \
  X(PFNGLGETPROGRAMINFOLOGPROC, GetProgramInfoLog)                 \
  X(PFNGLGETPROGRAMIVPROC, GetProgramiv)                           \
  X(PFNGLGETSHADERINFOLOGPROC, GetShaderInfoLog)                   \
  X(PFNGLGETSHADERIVPROC, GetShaderiv)                             \
  X(PFNGLGETSTRINGPROC, GetString)                                 \
  X(PFNGLGETUNIFORMBLOCKINDEXPROC, GetUniformBlockIndex)           \
  X(PFNGLGETUNIFORMLOCATIONPROC, GetUniformLocation)               \
  X(PFNGLLINKPROGRAMPROC, LinkProgram)                             \
  X(PFNGLPIXELSTOREIPROC, PixelStorei)                             \
  X(PFNGLREADPIXELSPROC, ReadPixels)                               \
  X(PFNGLRENDERBUFFERSTORAGEPROC, RenderbufferStorage)             \
  X(PFNGLSHADERSOURCEPROC, ShaderSource)                           \
  X(PFNGLTEXIMAGE2DPROC, TexImage2D)                               \
  X(PFNGLTEXIMAGE3DPROC, TexImage3D)                               \
  X(PFNGLTEXPARAMETERIPROC, TexParameteri)                         \
  X(PFNGLTEXSUBIMAGE3DPROC, TexSubImage3D)                         \
  X(PFNGLTRANSFORMFEEDBACKVARYINGSPROC, TransformFeedbackVaryings) \
  X(PFNGLUNIFORM1FPROC, Uniform1f)                                 \
  X(PFNGLUNIFORM1IPROC, Uniform1i)                                 \
  X(PFNGLUNIFORM1IVPROC, Uniform1iv)                               \
  X(PFNGLUNIFORM2FPROC, Uniform2f)                                 \
  X(PFNGLUNIFORM2FVPROC, Uniform2fv)                               \
  X(PFNGLUNIFORM3FVPROC, Uniform3fv)                               \
  X(PFNGLUNIFORM4FVPROC, Uniform4fv)                               \
  X(PFNGLUNIFORMBLOCKBINDINGPROC, UniformBlockBinding)             \
  X(PFNGLUNIFORMMATRIX3FVPROC, UniformMatrix3fv)                   \
  X(PFNGLUNIFORMMATRIX4FVPROC, UniformMatrix4fv)                   \
  X(PFNGLUSEPROGRAMPROC, UseProgram)                               \
  X(PFNGLVERTEXATTRIBIPOINTERPROC, VertexAttribIPointer)           \
  X(PFNGLVERTEXATTRIBPOINTERPROC, VertexAttribPointer)             \
  X(PFNGLVIEWPORTPROC, Viewport)

struct GlApi {
#define FVV_GL_MEMBER(type, name) type name = nullptr;
  FVV_GL_FUNCTIONS(FVV_GL_MEMBER)
#undef FVV_GL_MEMBER
};

using GlProcLoader = void* (*)(const char* name);
// Loads every function; an error names the first one missing.
Status LoadGlApi(GlProcLoader loader, GlApi* gl);

// The vertex shader both renderers use: linear-blend skinning with up to
// kMaxSkinBones bones in a std140 uniform block "Bones" (binding it needs a
// buffer of kMaxSkinBones * 64 bytes), attributes 0..4 = position, normal, uv,
// joints (uvec4), weights; uniforms u_view_proj, u_skinned (0: static geometry).
// Outputs v_world, v_normal, v_uv.
constexpr int kMaxSkinBones = 256;  // one std140 block of mat4: 16 KiB, the GL minimum
extern const char* const kSkinningVertexShader;

// Compiles and links a vertex + fragment shader pair; errors carry the GLSL log
// and start with `what`. With no fragment shader and a `feedback` output of
// the vertex shader: a program for transform feedback of that output.
StatusOr<GLuint> BuildProgram(const GlApi& gl, const char* vertex_source,
                              const char* fragment_source, const std::string& what,
                              const char* feedback = nullptr);
// The current framebuffer's lower-left width x height pixels as top-down rows
// of `channels` (1: red, 3: RGB) bytes.
Status ReadFramebuffer(const GlApi& gl, int width, int height, int channels,
                       std::vector<uint8_t>* pixels);

}  // namespace fvv

#endif  // FVV_PLAYER_RENDER_GL_API_H_
