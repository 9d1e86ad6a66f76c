// The person network names a body's left and right from how the person
// looks. Seen from behind, it sometimes names them the other way round in one
// camera while the other cameras agree, for a run of frames (on the real
// capture, cam02 over much of frames 35-70). Such a camera's sightings pull
// the fit towards a body turned round, and the frame is flagged as
// disagreeing with its keypoints. So before anything reads a frame's
// sightings, the cameras' labellings are made to agree: each choice of
// cameras to exchange left and right in is scored by how far every camera's
// sightings lie from the other cameras' triangulated into it
// (KeypointAgreement, averaged over the cameras), and the best is taken
// where it agrees far better than the sightings as seen and than any
// exchange in another camera. Scored camera by camera instead, a side view
// (left and right close in the image) gained twofold from exchanges that the
// truth showed wrong (docs/tracking.md).
#ifndef FVV_ENCODER_TRACK_SIGHTING_SIDES_H_
#define FVV_ENCODER_TRACK_SIGHTING_SIDES_H_

#include <cstdint>
#include <vector>

#include "container/cameras.h"
#include "encoder/track/joint_sighting.h"

namespace fvv {

// The other side's joint of a shoulder, elbow, wrist, hip, knee or ankle;
// any other joint unchanged.
int MirrorJoint(int joint);

struct SideExchange {
  enum class Limbs { kBody, kArms, kLegs };
  struct One {
    uint32_t camera = 0;
    Limbs limbs = Limbs::kBody;
  };
  std::vector<One> exchanges;  // in the order made
  // The cameras' mean KeypointAgreement (pixels) as seen and as left.
  double before_px = 0, after_px = 0;
};

// Exchanges left and right in one camera at a time (whole body, arms only or
// legs only), fewer than half of the cameras that see the person (more would
// be the others' labelling turned round, and nothing tells which half is
// right): each time the exchange that gives the lowest mean agreement, where
// it at least halves it and no exchange in another camera comes within a
// factor of 1.5 of it (unless both together halve it again); the last there
// is room for must also halve the worst camera's. `sightings` is per camera, as CaptureFrames gives
// them; three cameras or more must see the person.
// In a rig of more than `every_camera_tried_up_to` cameras seeing the person
// only the cameras that stand out (twice the median agreement or more) are
// tried: trying all is cubic in cameras, and a camera named the other way
// round stands out there (in fewer, it drags the others along and may not).
SideExchange ExchangeMislabelledSides(const std::vector<Camera>& cameras,
                                      std::vector<std::vector<JointSighting>>* sightings,
                                      size_t every_camera_tried_up_to = 8);

}  // namespace fvv

#endif  // FVV_ENCODER_TRACK_SIGHTING_SIDES_H_
