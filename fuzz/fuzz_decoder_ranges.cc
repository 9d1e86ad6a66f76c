// Fuzz target: the decoder library's byte-range input, as a web page fetching
// with HTTP Range requests uses it. The stream follows 2 leading bytes: the
// header boxes and index are added as the decoder asks, at most 1 + 61 * byte 0
// bytes a request; then every fragment as a prefix of its bytes past its head
// (byte 1 / 255 of the rest), and every frame decoded in RGB8.
#include <cstddef>
#include <cstdint>

#include "fvv/fvv_decoder.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 3) return 0;
  const uint64_t request = 1 + 61u * data[0];
  const uint64_t share = data[1];
  data += 2;
  size -= 2;
  fvv_decoder_settings settings;
  fvv_decoder_default_settings(&settings);
  settings.threads = 1;
  settings.memory_cap_bytes = 64u << 20;
  fvv::DecoderPtr dec = fvv::MakeDecoder(&settings);
  if (fvv_decoder_open_ranges(dec.get(), size) != FVV_OK) return 0;
  bool ready = false;
  for (int guard = 0; guard < 100000 && !ready; ++guard) {
    fvv_event event;
    if (fvv_decoder_process(dec.get(), &event) != FVV_OK) return 0;
    ready = event != FVV_EVENT_NEED_MORE_INPUT;
    uint64_t offset = 0, n = 0;
    if (!ready) {
      if (!fvv_decoder_wanted_range(dec.get(), &offset, &n) || offset >= size) return 0;
      n = n < request ? n : request;
      if (n > size - offset) n = size - offset;
      if (fvv_decoder_add_range(dec.get(), offset, data + offset, size_t(n)) != FVV_OK) return 0;
    }
  }
  if (!ready) return 0;
  const uint32_t fragments = fvv_decoder_fragment_count(dec.get());
  for (uint32_t i = 0; i < fragments; ++i) {
    fvv_fragment_info f;
    if (fvv_decoder_get_fragment(dec.get(), i, &f) != FVV_OK) return 0;
    const uint64_t prefix = f.head_size + (f.size - f.head_size) * share / 255;
    if (f.offset > size || prefix > size - f.offset) return 0;  // the index is checked: never
    fvv_decoder_add_range(dec.get(), f.offset, data + f.offset, size_t(prefix));
  }
  const uint32_t frames = fvv_decoder_frames_available(dec.get());
  for (uint32_t frame = 0; frame < frames && frame < 64; ++frame) {
    fvv::FramePtr decoded = fvv::DecodeFrame(dec.get(), frame, nullptr);
    (void)decoded;
  }
  return 0;
}
