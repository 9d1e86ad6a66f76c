// The GOP grid (SPEC.md 3.1): which frames and cameras a fragment, or an
// index entry, may cover. Shared by the fragment header, the index and both
// readers' walks, so that they refuse the same streams.
#ifndef FVV_CONTAINER_GOP_GRID_H_
#define FVV_CONTAINER_GOP_GRID_H_

#include <cstdint>
#include <string>

#include "codec/base/status.h"
#include "container/file_header.h"

namespace fvv {

// Frames [first_frame, first_frame + frame_count) of cameras [first_camera,
// first_camera + camera_count) must be one cell of the grid: aligned to it,
// the whole camera group, and the whole time span (when the header's
// frame_count is known, exactly the frames left in a short last span).
// **Corrupt** otherwise, the message starting with `at`.
Status CheckGridCell(const FileHeader& h, uint32_t first_frame, uint32_t frame_count,
                     uint32_t first_camera, uint32_t camera_count, const std::string& at);

// In a live stream (frame_count 0), where no header says where the frames
// end, only the last span may be short: a fragment of a later span than a
// short one is **Corrupt**; and the fragments of one span agree on its frame
// count (**Corrupt** otherwise). `previous_*` is the fragment before it in the
// stream.
Status CheckSpanOrder(const FileHeader& h, uint32_t previous_first_frame,
                      uint32_t previous_frame_count, uint32_t first_frame, uint32_t frame_count,
                      const std::string& at);

// A live stream ends after a whole time span: `fragments` in all must be a
// multiple of the camera groups (**Truncated** otherwise, the message starting
// with `at`). Nothing to check where the header's frame_count is known (the
// readers count its fragments against it).
Status CheckEndsAfterWholeSpan(const FileHeader& h, uint64_t fragments, const std::string& at);

}  // namespace fvv

#endif  // FVV_CONTAINER_GOP_GRID_H_
