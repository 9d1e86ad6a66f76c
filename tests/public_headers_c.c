/* The public headers compile alone, as C (DESIGN.md 4.1). */
#include "fvv/fvv_types.h"
/* (second include on purpose: include guards) */
#include "fvv/fvv_decoder.h"
#include "fvv/fvv_encoder.h"
#include "fvv/fvv_types.h"

int fvv_public_headers_compile_as_c(void) {
  fvv_decoder_settings settings;
  fvv_decoder_default_settings(&settings);
  fvv_encoder_settings encoder_settings;
  fvv_encoder_default_settings(&encoder_settings);
  return settings.decode_ahead && encoder_settings.atlas_size == 512 &&
         fvv_status_name(FVV_CORRUPT)[0] != '\0';
}
