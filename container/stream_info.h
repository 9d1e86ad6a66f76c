// Everything a stream declares before its fragments (SPEC.md 3.1-3.4, 3.6, 3.7),
// and the rules for interpreting those top-level boxes, shared by the
// incremental and the random-access reader.
#ifndef FVV_CONTAINER_STREAM_INFO_H_
#define FVV_CONTAINER_STREAM_INFO_H_

#include <vector>

#include "codec/base/status.h"
#include "container/body_model.h"
#include "container/box.h"
#include "container/cameras.h"
#include "container/file_header.h"
#include "container/index_box.h"
#include "container/motion_track.h"

namespace fvv {

struct StreamInfo {
  FileHeader header;
  std::vector<Camera> cameras;
  BodyModel model;
  MotionParams motion;
  Metadata metadata;
  std::vector<IndexEntry> index;

  bool has_header = false, has_cameras = false, has_model = false, has_motion = false;
  bool has_metadata = false, has_index = false;

  uint64_t expected_fragments() const {
    return uint64_t{header.time_spans()} * header.camera_groups();
  }
  // The stream's frames: the header's count, or in a live stream (SPEC.md
  // 3.1) those of its fragments as the index lists them (a file's walk
  // rebuilds it), which end after a whole time span.
  uint32_t frames() const {
    if (header.frame_count != 0 || index.empty()) return header.frame_count;
    return index.back().first_frame + index.back().frame_count;
  }
};

// Largest top-level box of this type a reader buffers (level limits).
uint64_t MaxTopLevelBoxSize(const StreamInfo& info, FourCC type);

// Interprets a complete top-level box other than 'frag'. Unknown non-essential
// boxes are ignored; unknown essential ones fail with kUnsupported.
Status ApplyTopLevelBox(const BoxHeader& box, const uint8_t* payload, StreamInfo* info);

// Fragments may follow only once header, cameras, model and motion parameters
// have been seen.
Status CheckReadyForFragments(const StreamInfo& info, uint64_t offset);

}  // namespace fvv

#endif  // FVV_CONTAINER_STREAM_INFO_H_
