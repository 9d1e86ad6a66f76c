#include "player/render/headless.h"

#include <GL/osmesa.h>

#include <string>

namespace fvv {
namespace {

void* OsMesaLoader(const char* name) { return reinterpret_cast<void*>(OSMesaGetProcAddress(name)); }

}  // namespace

StatusOr<std::unique_ptr<HeadlessContext>> HeadlessContext::Create(int width, int height) {
  if (width < 1 || height < 1 || width > 8192 || height > 8192) {
    return InvalidArgument("render size " + std::to_string(width) + "x" + std::to_string(height) +
                           " outside 1..8192");
  }
  const int attribs[] = {OSMESA_FORMAT,
                         OSMESA_RGBA,
                         OSMESA_DEPTH_BITS,
                         24,
                         OSMESA_PROFILE,
                         OSMESA_CORE_PROFILE,
                         OSMESA_CONTEXT_MAJOR_VERSION,
                         3,
                         OSMESA_CONTEXT_MINOR_VERSION,
                         3,
                         0};
  std::unique_ptr<HeadlessContext> c(new HeadlessContext());
  OSMesaContext ctx = OSMesaCreateContextAttribs(attribs, nullptr);
  if (!ctx) return Unsupported("OSMesa cannot create an OpenGL 3.3 core context");
  c->context_ = ctx;
  c->buffer_.resize(size_t(width) * height * 4);
  if (!OSMesaMakeCurrent(ctx, c->buffer_.data(), GL_UNSIGNED_BYTE, width, height)) {
    return Internal("OSMesaMakeCurrent failed");
  }
  c->width_ = width;
  c->height_ = height;
  FVV_RETURN_IF_ERROR(LoadGlApi(OsMesaLoader, &c->gl_));
  return c;
}

HeadlessContext::~HeadlessContext() {
  if (context_) OSMesaDestroyContext(static_cast<OSMesaContext>(context_));
}

}  // namespace fvv
