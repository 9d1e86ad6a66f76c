#include "player/playback/view_cameras.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace fvv {

std::vector<glm::vec3> CameraCentres(const fvv_decoder* decoder) {
  fvv_stream_info info;
  std::vector<glm::vec3> centres;
  if (fvv_decoder_get_info(decoder, &info) != FVV_OK) return centres;
  for (uint32_t c = 0; c < info.camera_count; ++c) {
    fvv_camera cam;
    if (fvv_decoder_get_camera(decoder, c, &cam) != FVV_OK) return {};
    centres.emplace_back(cam.centre[0], cam.centre[1], cam.centre[2]);
  }
  return centres;
}

namespace {

// The cameras in `mask` (0: all) by their angle to the view, closest first.
std::vector<std::pair<float, size_t>> ByAngle(const std::vector<glm::vec3>& centres, uint64_t mask,
                                              const glm::vec3& eye, const glm::vec3& target) {
  const size_t n = std::min<size_t>(centres.size(), 64);
  const glm::vec3 view = glm::normalize(eye - target);
  std::vector<std::pair<float, size_t>> angles;
  for (size_t c = 0; c < n; ++c) {
    if (mask != 0 && !((mask >> c) & 1)) continue;
    const glm::vec3 to_camera = glm::normalize(centres[c] - target);
    angles.emplace_back(std::acos(std::clamp(glm::dot(view, to_camera), -1.0f, 1.0f)), c);
  }
  std::sort(angles.begin(), angles.end());
  return angles;
}

}  // namespace

uint64_t ViewCameras(const std::vector<glm::vec3>& centres, const glm::vec3& eye,
                     const glm::vec3& target, float max_angle_deg, int min_cameras,
                     int max_cameras) {
  const std::vector<std::pair<float, size_t>> angles = ByAngle(centres, 0, eye, target);
  uint64_t mask = 0;
  const float limit = glm::radians(max_angle_deg);
  for (size_t k = 0; k < angles.size() && static_cast<int>(k) < max_cameras; ++k) {
    if (static_cast<int>(k) < min_cameras || angles[k].first < limit) {
      mask |= uint64_t{1} << angles[k].second;
    }
  }
  return mask;
}

uint64_t ClosestCameras(const std::vector<glm::vec3>& centres, uint64_t mask, const glm::vec3& eye,
                        const glm::vec3& target, int count) {
  const std::vector<std::pair<float, size_t>> angles = ByAngle(centres, mask, eye, target);
  uint64_t kept = 0;
  for (size_t k = 0; k < angles.size() && static_cast<int>(k) < count; ++k) {
    kept |= uint64_t{1} << angles[k].second;
  }
  return kept;
}

}  // namespace fvv
