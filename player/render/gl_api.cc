#include "player/render/gl_api.h"

#include <string>

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

}  // namespace fvv
