#include "container/gop_grid.h"

#include <algorithm>

namespace fvv {

Status CheckGridCell(const FileHeader& h, uint32_t first_frame, uint32_t frame_count,
                     uint32_t first_camera, uint32_t camera_count, const std::string& at) {
  const auto fail = [&](const std::string& why) {
    return Corrupt(at + "frames " + std::to_string(first_frame) + "+" +
                   std::to_string(frame_count) + ", cameras " + std::to_string(first_camera) + "+" +
                   std::to_string(camera_count) + " " + why);
  };
  if (first_frame % h.gop_frames != 0 || first_camera % h.gop_cameras != 0 || frame_count == 0 ||
      frame_count > h.gop_frames || first_camera >= h.camera_count ||
      (h.frame_count != 0 && first_frame >= h.frame_count)) {
    return fail("do not fit the header's GOP grid");
  }
  if (camera_count != std::min<uint32_t>(h.gop_cameras, h.camera_count - first_camera)) {
    return fail("are not the whole camera group");
  }
  if (h.frame_count != 0 &&
      frame_count != std::min<uint32_t>(h.gop_frames, h.frame_count - first_frame)) {
    return fail("are not the whole time span");
  }
  return Status::Ok();
}

Status CheckSpanOrder(const FileHeader& h, uint32_t previous_first_frame,
                      uint32_t previous_frame_count, uint32_t first_frame, uint32_t frame_count,
                      const std::string& at) {
  if (previous_frame_count < h.gop_frames && first_frame > previous_first_frame) {
    return Corrupt(at + "frames from " + std::to_string(first_frame) + " after a time span of " +
                   std::to_string(previous_frame_count) + " frames (only the last may be short)");
  }
  if (first_frame == previous_first_frame && frame_count != previous_frame_count) {
    return Corrupt(at + "the time span from frame " + std::to_string(first_frame) + " is " +
                   std::to_string(frame_count) + " frames here and " +
                   std::to_string(previous_frame_count) + " in the camera group before");
  }
  return Status::Ok();
}

Status CheckEndsAfterWholeSpan(const FileHeader& h, uint64_t fragments, const std::string& at) {
  const uint32_t groups = h.camera_groups();
  if (h.frame_count != 0 || fragments % groups == 0) return Status::Ok();
  return Truncated(at + "the stream ends inside time span " + std::to_string(fragments / groups) +
                   ", after " + std::to_string(fragments % groups) + " of its " +
                   std::to_string(groups) + " camera groups");
}

}  // namespace fvv
