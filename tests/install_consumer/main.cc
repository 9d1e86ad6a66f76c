// An application embedding fvv as its users would: find_package(fvv), link
// fvv::dec, include only <fvv/...>. Prints the frame count of a stream.
#include <cstdio>

#include "fvv/fvv_decoder.hpp"

int main(int argc, char** argv) {
  fvv::DecoderPtr dec = fvv::MakeDecoder();
  if (argc < 2 || !dec || fvv_decoder_open_file(dec.get(), argv[1]) != FVV_OK) {
    std::fprintf(stderr, "consumer: %s\n", dec ? fvv_decoder_error(dec.get()) : "no decoder");
    return 1;
  }
  fvv_stream_info info;
  fvv_decoder_get_info(dec.get(), &info);
  fvv::FramePtr frame = fvv::DecodeFrame(dec.get(), 0, nullptr);
  if (!frame) return 1;
  std::printf("frames %u\n", info.frame_count);
  return 0;
}
