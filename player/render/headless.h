// A headless OpenGL 3.3 core context (OSMesa, software rasterisation with
// llvmpipe): what `fvv render` and the tests draw into.
#ifndef FVV_PLAYER_RENDER_HEADLESS_H_
#define FVV_PLAYER_RENDER_HEADLESS_H_

#include <memory>
#include <vector>

#include "codec/base/status.h"
#include "player/render/gl_api.h"

namespace fvv {

class HeadlessContext {
 public:
  static StatusOr<std::unique_ptr<HeadlessContext>> Create(int width, int height);
  ~HeadlessContext();
  const GlApi& gl() const { return gl_; }
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  HeadlessContext() = default;
  void* context_ = nullptr;  // OSMesaContext
  std::vector<uint8_t> buffer_;
  GlApi gl_;
  int width_ = 0, height_ = 0;
};

}  // namespace fvv

#endif  // FVV_PLAYER_RENDER_HEADLESS_H_
