/* fvv export: a decoded stream's actor for the tools users already have.
 *
 * glTF 2.0 (.glb, or .gltf with a .bin and a .png beside it): the body model as a
 * skinned mesh (joint hierarchy, inverse bind matrices, the atlas UVs), the
 * motion track as an animation (each joint's rotation, the translations that
 * move, times from the stream's frame rate) and one colour texture: blended
 * from the decoded camera textures over the frames exported (each texel from
 * the cameras whose masks say they saw it, weighted by how squarely they saw
 * it), or one frame's. BVH: the motion track on the model's skeleton (offsets
 * in centimetres, each joint's rotation channels in its own order).
 *
 * Both read an open decoder (after FVV_EVENT_READY, with the frames exported
 * available) and write to a temporary file renamed into place; errors come back
 * as a status with the message in fvv_decoder_error(decoder). Link fvv::export.
 */
#ifndef FVV_FVV_EXPORT_H_
#define FVV_FVV_EXPORT_H_

#include <stdint.h>

#include "fvv/fvv_decoder.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
  uint32_t first_frame;  /* the first frame exported */
  uint32_t frame_count;  /* 0 = every frame from first_frame on */
  int32_t texture_frame; /* glTF: -1 = blended over the frames exported; else that frame's */
  uint32_t texture_size; /* glTF: the texture's width and height; 0 = the atlas's */
} fvv_export_settings;

FVV_EXPORT void fvv_export_default_settings(fvv_export_settings* settings);

/* .glb writes one binary file; .gltf writes JSON with PATH's stem .bin and .png
 * beside it. */
FVV_EXPORT fvv_status fvv_export_gltf(fvv_decoder* decoder, const fvv_export_settings* settings,
                                      const char* path);
FVV_EXPORT fvv_status fvv_export_bvh(fvv_decoder* decoder, const fvv_export_settings* settings,
                                     const char* path);

#ifdef __cplusplus
}
#endif

#endif /* FVV_FVV_EXPORT_H_ */
