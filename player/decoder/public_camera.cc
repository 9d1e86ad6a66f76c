#include "player/decoder/public_camera.h"

namespace fvv {

fvv_camera PublicCamera(const Camera& c) {
  fvv_camera out{};
  out.name = c.name.c_str();
  out.width = c.width;
  out.height = c.height;
  out.fx = c.fx;
  out.fy = c.fy;
  out.cx = c.cx;
  out.cy = c.cy;
  for (int i = 0; i < 5; ++i) out.distortion[i] = c.distortion[i];
  for (int i = 0; i < 9; ++i) out.rotation[i] = c.rotation[i];
  const auto centre = c.Centre();
  for (int i = 0; i < 3; ++i) {
    out.translation[i] = c.translation[i];
    out.centre[i] = centre[i];
  }
  return out;
}

}  // namespace fvv
