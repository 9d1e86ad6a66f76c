// The person network names a body's left and right from how the person
// looks. Side on or from behind, it sometimes names them the other way round
// in one camera while the other cameras agree, for a run of frames (on the
// real capture, cam02 over much of frames 35-70). Such a camera's sightings
// pull the fit towards a body turned round, and the frame is flagged as
// disagreeing with its keypoints. So before anything reads them, each
// camera's sightings are checked against the other cameras' sightings,
// triangulated and projected into it (KeypointAgreement), and their left and
// right exchanged (whole body, arms only or legs only) where that agrees far
// better (docs/tracking.md).
#ifndef FVV_ENCODER_TRACK_SIGHTING_SIDES_H_
#define FVV_ENCODER_TRACK_SIGHTING_SIDES_H_

#include <cstdint>
#include <vector>

#include "container/cameras.h"
#include "encoder/track/joint_sighting.h"

namespace fvv {

struct SideExchange {
  enum class Limbs { kBody, kArms, kLegs };
  uint32_t camera = 0;
  Limbs limbs = Limbs::kBody;
  double before_px = 0, after_px = 0;  // KeypointAgreement before and after
};

// The other side's joint of a shoulder, elbow, wrist, hip, knee or ankle;
// any other joint unchanged.
int MirrorJoint(int joint);

// Exchanges left and right in the camera whose agreement with the others
// improves most, while that improvement is at least twofold, one camera at a
// time (at most once each); `sightings` is per camera, as CaptureFrames gives
// them. Needs 3 cameras or more (a camera is checked against two others or
// more); returns what it exchanged.
std::vector<SideExchange> ExchangeMislabelledSides(
    const std::vector<Camera>& cameras, std::vector<std::vector<JointSighting>>* sightings);

}  // namespace fvv

#endif  // FVV_ENCODER_TRACK_SIGHTING_SIDES_H_
