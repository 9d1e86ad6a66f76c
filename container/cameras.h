// The camera box 'cams' (SPEC.md 3.2): calibrated pinhole cameras with
// Brown-Conrady distortion. The renderer needs them for view-dependent blending.
#ifndef FVV_CONTAINER_CAMERAS_H_
#define FVV_CONTAINER_CAMERAS_H_

#include <array>
#include <string>
#include <vector>

#include "codec/base/status.h"
#include "container/box.h"

namespace fvv {

struct Camera {
  std::string name;
  uint32_t width = 0, height = 0;  // image size in pixels
  double fx = 0, fy = 0, cx = 0, cy = 0;
  std::array<double, 5> distortion{};                         // k1 k2 p1 p2 k3 (OpenCV order)
  std::array<double, 9> rotation{1, 0, 0, 0, 1, 0, 0, 0, 1};  // R, row-major, world -> camera
  std::array<double, 3> translation{};                        // t in metres: x_cam = R x + t

  // Camera centre in world coordinates, -R^T t.
  std::array<double, 3> Centre() const;
};

std::vector<uint8_t> WriteCamerasBox(const std::vector<Camera>& cameras);
// `expected_count` is the header's camera count; the box must match it.
Status ReadCameras(const BoxHeader& box, const uint8_t* payload, uint32_t expected_count,
                   std::vector<Camera>* cameras);

}  // namespace fvv

#endif  // FVV_CONTAINER_CAMERAS_H_
