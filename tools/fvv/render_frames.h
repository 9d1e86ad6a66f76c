// What `fvv render` draws, frame by frame: a .fvv stream decoded and drawn by
// Renderer II (the atlas textures blended by viewing angle), or a capture drawn
// by Renderer I (the posed model textured directly from the camera images by
// projective texturing). The views (orbit, camera, path, contact sheet) and the
// outputs are the command's; these only load a frame and draw it.
#ifndef FVV_TOOLS_FVV_RENDER_FRAMES_H_
#define FVV_TOOLS_FVV_RENDER_FRAMES_H_

#include <cstdint>
#include <functional>
#include <glm/vec3.hpp>
#include <memory>
#include <string>
#include <vector>

#include "codec/base/status.h"
#include "encoder/shape/projective_texturing.h"
#include "fvv/fvv_decoder.h"
#include "player/render/gl_api.h"
#include "player/render/renderer.h"

namespace fvv {

class RenderFrames {
 public:
  virtual ~RenderFrames() = default;
  uint32_t first_frame() const { return first_; }
  uint32_t last_frame() const { return last_; }
  double frame_rate() const { return fps_; }
  const std::vector<fvv_camera>& cameras() const { return cameras_; }

  // Makes the renderer; the GL context must be current.
  virtual Status CreateRenderer(const GlApi& gl) = 0;
  // Loads frame `frame` (first..last) into the renderer; `root` is the actor's
  // root joint, where orbits look.
  virtual Status Load(uint32_t frame, glm::vec3* root) = 0;
  virtual Status Draw(const RenderView& view, int width, int height) = 0;
  virtual Status ReadRgb(int width, int height, std::vector<uint8_t>* rgb) = 0;
  // The pixels the actor covers (255) after Draw; Unsupported where the
  // renderer cannot tell (Renderer I resolves every pixel).
  virtual Status ReadCoverage(int width, int height, std::vector<uint8_t>* coverage) = 0;
  // The timing line of the run after `frames` frames (what loading cost).
  virtual std::string LoadTimes(uint32_t frames) const = 0;

 protected:
  uint32_t first_ = 0, last_ = 0;
  double fps_ = 25;
  std::vector<fvv_camera> cameras_;
};

struct StreamRenderOptions {
  uint64_t bytes = 0;  // texture bytes per GOP fragment (0: all)
  double max_ms = 0;   // or a decoding time per GOP
  // An RGB image of the atlas's size drawn as every camera's texture (an
  // exported glTF's single texture): the model in its decoded poses, with no
  // view-dependent blending; the stream's textures are not decoded.
  std::string texture;
};
StatusOr<std::unique_ptr<RenderFrames>> OpenStreamFrames(const std::string& path,
                                                         const StreamRenderOptions& options);

struct CaptureRenderOptions {
  std::string poses;  // poses.json or truth; empty: track the capture
  uint32_t first = 0, last = UINT32_MAX;
  ProjectiveOptions projective;
  // The surface of every frame tracked from the capture's silhouettes (as
  // fvv encode --surface does) and drawn instead of the fitted body.
  bool surface = false;
  std::function<void(const std::string&)> progress;
};
StatusOr<std::unique_ptr<RenderFrames>> OpenCaptureFrames(const std::string& path,
                                                          const CaptureRenderOptions& options);

}  // namespace fvv

#endif  // FVV_TOOLS_FVV_RENDER_FRAMES_H_
