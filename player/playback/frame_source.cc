#include "player/playback/frame_source.h"

#include <string>

namespace fvv {

bool DecoderFrameSource::Ready(uint32_t frame, const GopRequest& request) {
  return fvv_decoder_frame_ready(dec_, frame, &request.budget) != 0;
}

void DecoderFrameSource::Prefetch(uint32_t frame, const GopRequest& request) {
  fvv_decoder_prefetch(dec_, frame, &request.budget);
}

StatusOr<bool> DecoderFrameSource::Take(uint32_t frame, const GopRequest& request,
                                        fvv_decode_report* report) {
  FramePtr next = DecodeFrame(dec_, frame, &request.budget);
  if (!next) return Internal("frame " + std::to_string(frame) + ": " + fvv_decoder_error(dec_));
  frame_ = std::move(next);
  *report = frame_->report;
  return true;
}

uint32_t DecoderFrameSource::CamerasTaken() const {
  if (!frame_) return 0;
  uint32_t cameras = 0;
  for (uint32_t c = 0; c < frame_->camera_count; ++c) cameras += frame_->views[c].pixels != nullptr;
  return cameras;
}

}  // namespace fvv
