// An exported actor as glTF 2.0: a skinned mesh (one node per joint, inverse
// bind matrices, the atlas UVs), the motion as one animation (every joint's
// rotation, the translations that change, linear between frames) and the
// colour texture as an unlit material (the capture's light is in it).
#ifndef FVV_PLAYER_EXPORT_GLTF_WRITER_H_
#define FVV_PLAYER_EXPORT_GLTF_WRITER_H_

#include <string>

#include "codec/base/status.h"
#include "player/export/exported_actor.h"

namespace fvv {

// `path` ending in .glb: one binary file; in .gltf: JSON, with the buffer and
// the texture beside it as STEM.bin and STEM.png. Every file is written whole
// or not at all.
Status WriteGltf(const ExportedActor& actor, const std::string& path);

}  // namespace fvv

#endif  // FVV_PLAYER_EXPORT_GLTF_WRITER_H_
