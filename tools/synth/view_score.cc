#include "tools/synth/view_score.h"

#include <algorithm>
#include <cmath>

#include "encoder/capture/capture.h"
#include "fvv/fvv_decoder.hpp"
#include "player/decoder/c_api_internal.h"
#include "player/decoder/public_camera.h"
#include "player/render/headless.h"
#include "player/render/renderer.h"

namespace fvv {

double ActorPsnr(const std::vector<uint8_t>& rgb, const Image& truth, const Image& silhouette,
                 uint64_t* pixels) {
  double sse = 0;
  uint64_t n = 0;
  for (size_t i = 0; i < silhouette.pixels.size(); ++i) {
    if (!silhouette.pixels[i]) continue;
    ++n;
    for (int k = 0; k < 3; ++k) {
      const double d = double(rgb[i * 3 + k]) - truth.pixels[i * 3 + k];
      sse += d * d;
    }
  }
  if (pixels) *pixels = n;
  return n ? 10 * std::log10(255.0 * 255.0 / std::max(sse / (3.0 * n), 1e-9)) : 0.0;
}

StatusOr<double> HeldOutStreamPsnr(const std::string& stream, const std::string& capture,
                                   uint32_t camera, uint32_t frame) {
  StatusOr<Capture> held = LoadCapture(capture + "/truth/heldout");
  if (!held.ok()) return held.status();
  if (camera >= held->cameras.size()) return InvalidArgument("no such held-out camera");
  CaptureReader reader(*held);
  const Camera& cam = held->cameras[camera].calibration;
  DecoderPtr dec = MakeDecoder();
  if (!dec || fvv_decoder_open_file(dec.get(), stream.c_str()) != FVV_OK) {
    return dec ? DecoderStatus(dec.get()) : Internal("cannot create a decoder");
  }
  fvv_stream_info info;
  fvv_decoder_get_info(dec.get(), &info);
  fvv_model model;
  fvv_decoder_get_model(dec.get(), &model);
  const int w = int(cam.width), h = int(cam.height);
  StatusOr<std::unique_ptr<HeadlessContext>> ctx = HeadlessContext::Create(w, h);
  if (!ctx.ok()) return ctx.status();
  StatusOr<std::unique_ptr<Renderer>> r = Renderer::Create(
      (*ctx)->gl(), model, DecoderCameras(dec.get()), info.atlas_width, info.atlas_height);
  if (!r.ok()) return r.status();
  FramePtr f = DecodeFrame(dec.get(), frame, nullptr);
  if (!f) return DecoderStatus(dec.get());
  RenderView view;
  CameraViewProjection(PublicCamera(cam), 0.05f, 50.0f, &view.view, &view.projection);
  const auto c = cam.Centre();
  view.eye = glm::vec3(c[0], c[1], c[2]);
  std::vector<uint8_t> rgb;
  FVV_RETURN_IF_ERROR((*r)->SetFrame(*f));
  FVV_RETURN_IF_ERROR((*r)->Draw(view, w, h));
  FVV_RETURN_IF_ERROR((*r)->ReadRgb(w, h, &rgb));
  StatusOr<Image> truth = reader.ReadFrame(camera, frame);
  if (!truth.ok()) return truth.status();
  StatusOr<Image> silhouette = reader.ReadSilhouette(camera, frame);
  if (!silhouette.ok()) return silhouette.status();
  return ActorPsnr(rgb, *truth, *silhouette);
}

}  // namespace fvv
