// The C API of include/fvv/fvv_export.h: argument checks, then gather and write.
#include <string>

#include "fvv/fvv_export.h"
#include "player/decoder/c_api_internal.h"
#include "player/export/bvh_writer.h"
#include "player/export/exported_actor.h"
#include "player/export/gltf_writer.h"

namespace {

fvv_status Export(fvv_decoder* d, const fvv_export_settings* settings, const char* path,
                  bool gltf) {
  if (!d) return FVV_INVALID_ARGUMENT;
  if (!path || !*path) {
    return fvv::ReportDecoderStatus(d, fvv::InvalidArgument("export: no output path"));
  }
  fvv_export_settings s;
  fvv_export_default_settings(&s);
  if (settings) s = *settings;
  auto actor = fvv::GatherActor(d, s, gltf);
  if (!actor.ok()) return fvv::ReportDecoderStatus(d, actor.status());
  return fvv::ReportDecoderStatus(
      d, gltf ? fvv::WriteGltf(*actor, path) : fvv::WriteBvh(*actor, path));
}

}  // namespace

extern "C" {

void fvv_export_default_settings(fvv_export_settings* settings) {
  if (!settings) return;
  settings->first_frame = 0;
  settings->frame_count = 0;
  settings->texture_frame = -1;
  settings->texture_size = 0;
}

fvv_status fvv_export_gltf(fvv_decoder* decoder, const fvv_export_settings* settings,
                           const char* path) {
  return Export(decoder, settings, path, true);
}

fvv_status fvv_export_bvh(fvv_decoder* decoder, const fvv_export_settings* settings,
                          const char* path) {
  return Export(decoder, settings, path, false);
}

}  // extern "C"
