// For libraries and programs over the decoder's C API (the exporter, the
// CLI): what an open fvv_decoder holds beyond the public arrays, and its
// last status.
#ifndef FVV_PLAYER_DECODER_C_API_INTERNAL_H_
#define FVV_PLAYER_DECODER_C_API_INTERNAL_H_

#include "codec/base/status.h"
#include "container/stream_info.h"
#include "fvv/fvv_decoder.h"

namespace fvv {

// The stream's header boxes (model, skeleton, motion steps); null before
// FVV_EVENT_READY.
const StreamInfo* DecoderStreamInfo(const fvv_decoder* decoder);
// Sets the message fvv_decoder_error returns and gives the status code.
fvv_status ReportDecoderStatus(fvv_decoder* decoder, const Status& status);
// The status of the decoder's last call, for callers that carry Status on
// (fvv_decoder_error is its ToString()).
Status DecoderStatus(const fvv_decoder* decoder);

}  // namespace fvv

#endif  // FVV_PLAYER_DECODER_C_API_INTERNAL_H_
