// An application handing the actor to an engine: find_package(fvv COMPONENTS
// export), link fvv::export, write a stream's actor as glTF.
#include <cstdio>

#include "fvv/fvv_decoder.hpp"
#include "fvv/fvv_export.h"

int main(int argc, char** argv) {
  fvv::DecoderPtr dec = fvv::MakeDecoder();
  if (argc < 3 || !dec || fvv_decoder_open_file(dec.get(), argv[1]) != FVV_OK ||
      fvv_export_gltf(dec.get(), nullptr, argv[2]) != FVV_OK) {
    std::fprintf(stderr, "export consumer: %s\n",
                 dec ? fvv_decoder_error(dec.get()) : "no decoder");
    return 1;
  }
  std::printf("exported\n");
  return 0;
}
