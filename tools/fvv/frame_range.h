// The --frames A:B option of the capture commands.
#ifndef FVV_TOOLS_FVV_FRAME_RANGE_H_
#define FVV_TOOLS_FVV_FRAME_RANGE_H_

#include <cstdio>
#include <string>

#include "codec/base/status.h"

namespace fvv {

// "A:B" (A <= B) into *first and *last; empty text leaves them as they are.
inline Status ParseFrameRange(const std::string& text, uint32_t* first, uint32_t* last) {
  if (text.empty()) return Status::Ok();
  unsigned f0 = 0, f1 = 0;
  char tail = 0;
  if (std::sscanf(text.c_str(), "%u:%u%c", &f0, &f1, &tail) != 2 || f0 > f1) {
    return InvalidArgument("--frames " + text + " is not a range A:B");
  }
  *first = f0, *last = f1;
  return Status::Ok();
}

}  // namespace fvv

#endif  // FVV_TOOLS_FVV_FRAME_RANGE_H_
