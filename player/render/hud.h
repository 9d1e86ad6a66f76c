// The player's on-screen HUD: lines of text in a built-in 5x7 pixel font drawn
// over the rendered frame on an opaque panel, as plain geometry (one quad per
// lit font pixel), so it needs no font files, textures or blending and looks
// the same under OSMesa and GLFW.
#ifndef FVV_PLAYER_RENDER_HUD_H_
#define FVV_PLAYER_RENDER_HUD_H_

#include <memory>
#include <string>
#include <vector>

#include "player/render/gl_api.h"

namespace fvv {

class HudOverlay {
 public:
  static constexpr int kGlyphWidth = 5, kGlyphHeight = 7;
  static constexpr int kAdvance = 6, kLineHeight = 9, kMargin = 2;  // in font pixels

  static StatusOr<std::unique_ptr<HudOverlay>> Create(const GlApi& gl);
  ~HudOverlay();
  HudOverlay(const HudOverlay&) = delete;
  HudOverlay& operator=(const HudOverlay&) = delete;

  // Draws `lines` at the top left of the current width x height framebuffer,
  // each font pixel `scale` x `scale` screen pixels (letters in upper case;
  // characters the font lacks show as '?').
  Status Draw(const std::vector<std::string>& lines, int width, int height, int scale);

  // Font pixels `text` lights (tests count them on screen).
  static int LitPixels(const std::string& text);
  // Panel size in screen pixels for `lines` at `scale`.
  static void PanelSize(const std::vector<std::string>& lines, int scale, int* width, int* height);

 private:
  explicit HudOverlay(const GlApi& gl) : gl_(gl) {}
  const GlApi& gl_;
  GLuint program_ = 0, vao_ = 0, vbo_ = 0;
  GLint colour_location_ = -1, viewport_location_ = -1;
};

}  // namespace fvv

#endif  // FVV_PLAYER_RENDER_HUD_H_
