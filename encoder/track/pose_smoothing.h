// Temporal smoothing of tracked poses.
//
// Each frame is fitted to its own silhouettes, so a pose carries frame-to-frame
// jitter the actor never made: on the demo capture about 0.02 rad per DOF
// between neighbouring frames, and up to 0.16 rad on a shoulder the torso hides
// (bench/track_bench). Textures resampled with a jittering pose slide across the
// atlas from frame to frame, and the codec's temporal transform pays for every
// slide. A Gaussian over a few neighbouring frames, which are already tracked
// when the frame is resampled, removes most of the jitter and keeps the
// motion: with sigma = 1 frame, motion at 3.3 Hz (at 25 fps) keeps 71 % of its
// amplitude, and human motion lies mostly below that.
#ifndef FVV_ENCODER_TRACK_POSE_SMOOTHING_H_
#define FVV_ENCODER_TRACK_POSE_SMOOTHING_H_

#include <cstddef>
#include <vector>

namespace fvv {

struct PoseSmoothing {
  double sigma_frames = 0;  // standard deviation of the Gaussian in frames; 0: off
  // Frames on each side of a frame that its smoothed pose reads.
  int Radius() const;
};

// The smoothed pose of poses[centre]: a Gaussian-weighted mean over
// poses[centre - Radius() .. centre + Radius()], cut at the ends of `poses`.
// Frames with trusted[i] false (fits flagged as poor) do not pull their
// neighbours; a frame always counts itself. Angles (angular[d]) are averaged
// after unwrapping them to within pi of the centre frame's value, so a DOF
// that crosses +-pi is not averaged to its opposite.
std::vector<double> SmoothPose(const std::vector<std::vector<double>>& poses,
                               const std::vector<bool>& trusted, const std::vector<bool>& angular,
                               size_t centre, const PoseSmoothing& smoothing);

}  // namespace fvv

#endif  // FVV_ENCODER_TRACK_POSE_SMOOTHING_H_
