// Fuzz target: the decoder library as players use it, through its C API:
// bytes pushed in chunks (size from byte 0), events processed, every available
// frame decoded in RGB8. Byte 1 sets the budget: below 128, a byte budget of
// 16 bytes a step (0: none); from 128, a time budget that runs out at once with
// a quality floor of (byte - 128) / 127 of each stream.
#include <cstddef>
#include <cstdint>

#include "fvv/fvv_decoder.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 2) return 0;
  const size_t chunk = 1 + data[0] % 251;
  fvv_decode_budget budget{};
  if (data[1] < 128) {
    budget.max_bytes_per_gop = data[1] * 16u;
  } else {
    budget.max_ms_per_gop = 1e-3;
    budget.floor_share = (data[1] - 128) / 127.0;
  }
  data += 2;
  size -= 2;
  fvv_decoder_settings settings;
  fvv_decoder_default_settings(&settings);
  settings.threads = 1;
  settings.decode_ahead = 0;
  settings.memory_cap_bytes = 64u << 20;
  fvv::DecoderPtr dec = fvv::MakeDecoder(&settings);
  size_t pos = 0;
  uint32_t decoded = 0;
  for (int guard = 0; guard < 100000; ++guard) {
    fvv_event event;
    if (fvv_decoder_process(dec.get(), &event) != FVV_OK || event == FVV_EVENT_END) break;
    if (event == FVV_EVENT_NEED_MORE_INPUT) {
      if (pos == size) {
        fvv_decoder_push_end(dec.get());
      } else {
        const size_t n = chunk < size - pos ? chunk : size - pos;
        fvv_decoder_push(dec.get(), data + pos, n);
        pos += n;
      }
    } else if (event == FVV_EVENT_FRAMES) {
      for (; decoded < fvv_decoder_frames_available(dec.get()); ++decoded) {
        fvv::FramePtr frame = fvv::DecodeFrame(dec.get(), decoded, &budget);
        if (!frame) break;
      }
    }
  }
  return 0;
}
