// The --cameras NAME,NAME option of the capture commands.
#ifndef FVV_TOOLS_FVV_CAMERA_NAMES_H_
#define FVV_TOOLS_FVV_CAMERA_NAMES_H_

#include <algorithm>
#include <string>
#include <vector>

#include "codec/base/status.h"
#include "encoder/capture/capture.h"

namespace fvv {

// The cameras named (all where none is), as indices into the capture's; a
// name the capture does not have is an error.
inline StatusOr<std::vector<size_t>> ChooseCameras(const Capture& cap,
                                                   const std::vector<std::string>& names) {
  std::vector<size_t> chosen;
  for (size_t c = 0; c < cap.cameras.size(); ++c) {
    if (names.empty() ||
        std::find(names.begin(), names.end(), cap.cameras[c].calibration.name) != names.end()) {
      chosen.push_back(c);
    }
  }
  for (const std::string& name : names) {
    const bool known = std::any_of(cap.cameras.begin(), cap.cameras.end(),
                                   [&](const auto& c) { return c.calibration.name == name; });
    if (!known) return InvalidArgument("--cameras: the capture has no camera \"" + name + "\"");
  }
  return chosen;
}

}  // namespace fvv

#endif  // FVV_TOOLS_FVV_CAMERA_NAMES_H_
