// C++ RAII wrappers of the fvv decoder C API (fvv_decoder.h).
//
//   fvv::DecoderPtr dec = fvv::MakeDecoder();
//   if (!dec || fvv_decoder_open_file(dec.get(), path) != FVV_OK) ...
//   fvv::FramePtr frame = fvv::DecodeFrame(dec.get(), 0, nullptr);
#ifndef FVV_FVV_DECODER_HPP_
#define FVV_FVV_DECODER_HPP_

#include <memory>

#include "fvv/fvv_decoder.h"

namespace fvv {

struct DecoderDeleter {
  void operator()(fvv_decoder* d) const { fvv_decoder_destroy(d); }
};
struct FrameDeleter {
  void operator()(fvv_frame* f) const { fvv_frame_release(f); }
};
using DecoderPtr = std::unique_ptr<fvv_decoder, DecoderDeleter>;
using FramePtr = std::unique_ptr<fvv_frame, FrameDeleter>;

// A decoder with the given (or default) settings; null on failure (*status says why).
inline DecoderPtr MakeDecoder(const fvv_decoder_settings* settings = nullptr,
                              fvv_status* status = nullptr) {
  fvv_decoder* d = nullptr;
  const fvv_status s = fvv_decoder_create(settings, &d);
  if (status) *status = s;
  return DecoderPtr(s == FVV_OK ? d : nullptr);
}

// The frame, or null on failure (*status says why; fvv_decoder_error has the message).
inline FramePtr DecodeFrame(fvv_decoder* decoder, uint32_t index, const fvv_decode_budget* budget,
                            fvv_status* status = nullptr) {
  fvv_frame* f = nullptr;
  const fvv_status s = fvv_decoder_decode_frame(decoder, index, budget, &f);
  if (status) *status = s;
  return FramePtr(s == FVV_OK ? f : nullptr);
}

}  // namespace fvv

#endif  // FVV_FVV_DECODER_HPP_
