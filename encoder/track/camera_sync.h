// Whether a capture's cameras run in step, and by how many frames each is
// off: cameras started by hand, or by a trigger some missed, record the same
// moment as different frame numbers, and a moving actor then lies in
// different places in different cameras. The person network's body keypoints
// in every camera over a span of frames become rays; for each pair of cameras
// and each shift of one's frames against the other's, the median over frames
// of how far apart the two cameras' rays to the same joint pass (in pixels).
// The offsets are those whose pairs' shifts sum to the least (every
// combination for up to 2 million, else coordinate descent).
#ifndef FVV_ENCODER_TRACK_CAMERA_SYNC_H_
#define FVV_ENCODER_TRACK_CAMERA_SYNC_H_

#include <functional>
#include <string>
#include <vector>

#include "codec/base/status.h"
#include "container/cameras.h"
#include "encoder/capture/capture.h"
#include "encoder/track/capture_frames.h"
#include "encoder/track/joint_sighting.h"
#include "encoder/track/person_observer.h"

namespace fvv {

// How far (pixels) camera `k`'s confident sightings lie from the other
// cameras' sightings triangulated (a view off by more than `tolerance_px`
// left out where the rest agree) and projected into camera k: what any body
// meeting the other cameras' keypoints reaches in camera k, keypoint noise and
// calibration together. -1 when nothing is seen in camera k and two others.
double KeypointAgreement(const std::vector<Camera>& cameras, uint32_t k,
                         const std::vector<std::vector<JointSighting>>& sightings,
                         double tolerance_px);
// The same sightings' residuals one by one: where camera k sees each joint
// minus where the other cameras put it (pixels).
std::vector<Eigen::Vector2d> KeypointResiduals(
    const std::vector<Camera>& cameras, uint32_t k,
    const std::vector<std::vector<JointSighting>>& sightings, double tolerance_px);

struct FrameOffsets {
  // Per camera: frames to skip at the start of its recording (added to its
  // frames' `first`), the smallest 0.
  std::vector<int> offsets;
  // Per camera: KeypointAgreement's median over the span, as the capture is
  // and with the offsets.
  std::vector<double> before_px, after_px;
  uint32_t frames = 0;  // frames compared
};

struct FrameOffsetOptions {
  uint32_t first = 0, last = 59;  // the span compared (clamped to the capture)
  int max_offset = 8;             // frames either way
  double tolerance_px = 20;       // KeypointAgreement's
  std::function<void(const std::string&)> progress;
};

StatusOr<FrameOffsets> EstimateFrameOffsets(const Capture& capture, PersonObserver* observer,
                                            const FrameOffsetOptions& options);

// The same from sightings already read (`[frame][camera]`, consecutive frames;
// options.first and last are not read): what fvv track checks on the frames
// it tracked.
StatusOr<FrameOffsets> EstimateFrameOffsets(const std::vector<Camera>& cameras,
                                            const CaptureSightings& sightings,
                                            const FrameOffsetOptions& options);

// Whether offsets found by EstimateFrameOffsets say the cameras run out of
// step: over at least kMinStepCheckFrames frames compared, two cameras 2
// frames apart or more, and the cameras' keypoints then agreeing better by
// 5 % or more. The search always finds some offsets that help a little: on a
// real 60 fps take already in step it found cameras a frame apart, gaining or
// losing about a pixel of 20-30 (docs/tracking.md). Over a few frames, one
// camera's keypoints gone astray for a moment (someone passing close in front
// of it) move the medians more than a step does.
constexpr uint32_t kMinStepCheckFrames = 12;
bool CamerasOutOfStep(const FrameOffsets& offsets);

}  // namespace fvv

#endif  // FVV_ENCODER_TRACK_CAMERA_SYNC_H_
