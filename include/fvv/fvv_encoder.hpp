// C++ RAII wrapper of the fvv encoder C API (fvv_encoder.h).
//
//   fvv::EncoderPtr enc = fvv::MakeEncoder();
//   if (!enc || fvv_encoder_encode_capture(enc.get(), "take1", "take1.fvv", nullptr) != FVV_OK)
//     ... fvv_encoder_error(enc.get())
#ifndef FVV_FVV_ENCODER_HPP_
#define FVV_FVV_ENCODER_HPP_

#include <memory>

#include "fvv/fvv_encoder.h"

namespace fvv {

struct EncoderDeleter {
  void operator()(fvv_encoder* e) const { fvv_encoder_destroy(e); }
};
using EncoderPtr = std::unique_ptr<fvv_encoder, EncoderDeleter>;

// An encoder with the given (or default) settings; null on failure (*status says why).
inline EncoderPtr MakeEncoder(const fvv_encoder_settings* settings = nullptr,
                              fvv_status* status = nullptr) {
  fvv_encoder* e = nullptr;
  const fvv_status s = fvv_encoder_create(settings, &e);
  if (status) *status = s;
  return EncoderPtr(s == FVV_OK ? e : nullptr);
}

}  // namespace fvv

#endif  // FVV_FVV_ENCODER_HPP_
