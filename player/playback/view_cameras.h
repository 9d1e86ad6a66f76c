// Which cameras a view needs: those the blend weighs by viewing angle. No GL:
// the native renderer, the playback loop and the web player share it.
#ifndef FVV_PLAYER_PLAYBACK_VIEW_CAMERAS_H_
#define FVV_PLAYER_PLAYBACK_VIEW_CAMERAS_H_

#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "fvv/fvv_decoder.h"

namespace fvv {

// The centres of a ready decoder's cameras (what ViewCameras takes).
std::vector<glm::vec3> CameraCentres(const fvv_decoder* decoder);

// The most cameras a view blends and decodes. In a ring of 8 the cameras within
// 90-110 degrees of a view are 5 to 6; a dome of 30 to 100 has several times
// as many there, each costing a decode, a depth map and a step of every
// fragment's blend, while the blend's weights fall so fast with the angle
// (container/geometric_visibility.h) that past the closest few only cameras
// that see what those cannot add anything.
constexpr int kMaxViewCameras = 8;

// The cameras a view blends with real weight: those seeing the actor (at
// `target`) from within `max_angle_deg` of the viewing direction, at least the
// `min_cameras` closest in angle and at most the `max_cameras` closest. As an
// fvv_decode_budget.camera_mask: with the default exponent a camera 90 degrees
// off weighs under 1 % of one 22 degrees off, so leaving such cameras
// undecoded changes little on screen.
uint64_t ViewCameras(const std::vector<glm::vec3>& centres, const glm::vec3& eye,
                     const glm::vec3& target, float max_angle_deg = 90.0f, int min_cameras = 3,
                     int max_cameras = kMaxViewCameras);

// Of the cameras in `mask` (0: all), the `count` closest in angle to the view
// from `eye` to `target`.
uint64_t ClosestCameras(const std::vector<glm::vec3>& centres, uint64_t mask, const glm::vec3& eye,
                        const glm::vec3& target, int count);

}  // namespace fvv

#endif  // FVV_PLAYER_PLAYBACK_VIEW_CAMERAS_H_
