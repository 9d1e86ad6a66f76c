// Poses computed elsewhere, for encoding without the tracker: a poses.json as
// `fvv track` writes it (or a studio's own tracking in that form), or the
// truth.json of a synthetic capture with the built-in actor.
#ifndef FVV_ENCODER_ENCODE_POSE_FILE_H_
#define FVV_ENCODER_ENCODE_POSE_FILE_H_

#include <string>
#include <vector>

#include "codec/base/status.h"
#include "encoder/body/generic_body.h"

namespace fvv {

struct PoseSequence {
  BodyShape shape;
  uint32_t first_frame = 0;                // capture frame of poses[0]
  std::vector<std::vector<double>> poses;  // consecutive frames, generic-body DOF order
  uint32_t atlas_size = 0;  // textures.json: the atlas its textures are in; 0 otherwise
  uint32_t crc32c = 0;      // LoadPoseFile: the file's CRC-32C (shards check they share it)
};

// Parses poses.json / truth.json text; `what` names the file in errors. The DOF
// names must be the generic body's, the frames consecutive, every value finite.
StatusOr<PoseSequence> ParsePoseFile(const std::string& text, const std::string& what);
// `path`: a file, or a directory holding truth/truth.json (a synthetic capture).
StatusOr<PoseSequence> LoadPoseFile(const std::string& path);
// The DOF names poses.json lists ("l_knee.rx").
std::vector<std::string> GenericDofNames();

}  // namespace fvv

#endif  // FVV_ENCODER_ENCODE_POSE_FILE_H_
