// An application embedding the fvv encoder as its users would:
// find_package(fvv COMPONENTS encoder), link fvv::encoder, include only
// <fvv/...>. Encodes CAPTURE (with the poses in POSES) into OUT.fvv and prints
// the frame count and whether the PSNR report is sensible.
#include <cstdio>

#include "fvv/fvv_encoder.hpp"

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: encode_consumer CAPTURE POSES OUT.fvv\n");
    return 2;
  }
  fvv_encoder_settings settings;
  fvv_encoder_default_settings(&settings);
  settings.atlas_size = 128;
  settings.gop_frames = 2;
  settings.poses = argv[2];
  fvv::EncoderPtr enc = fvv::MakeEncoder(&settings);
  if (!enc) {
    std::fprintf(stderr, "encode_consumer: %s\n", fvv_encoder_settings_error());
    return 1;
  }
  fvv_encode_report report;
  if (fvv_encoder_encode_capture(enc.get(), argv[1], argv[3], &report) != FVV_OK) {
    std::fprintf(stderr, "encode_consumer: %s\n", fvv_encoder_error(enc.get()));
    return 1;
  }
  std::printf("encoded %u frames, psnr %s\n", report.frames,
              report.psnr_rgb > 15 && report.psnr_rgb < 99 ? "ok" : "odd");
  return 0;
}
