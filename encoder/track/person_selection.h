// Which of the people each camera sees is the actor: the person whose hips
// agree in 3D across the cameras, inside the capture volume. A bystander seen
// by one camera, or by several at a place the rays do not agree on, or walking
// outside the volume the cameras surround, is not chosen.
#ifndef FVV_ENCODER_TRACK_PERSON_SELECTION_H_
#define FVV_ENCODER_TRACK_PERSON_SELECTION_H_

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "container/cameras.h"

namespace fvv {

struct ActorChoice {
  std::optional<Eigen::Vector3d> hips;  // world (y up); none when no two cameras agree
  std::vector<int> chosen;              // per camera: the candidate's index, or -1
  int cameras_agreeing = 0;
};

// A person's hips' centre in one image, and how far off it may be (pixels;
// a share of the person's size in that image).
struct HipSighting {
  Eigen::Vector2d hips = Eigen::Vector2d::Zero();
  double tolerance = 0;
};

// `candidates[c]`: the people camera c sees. `known[c]`: where camera c
// already follows the actor, if it does; those cameras anchor the choice. A
// candidate is the actor's in camera c when the chosen hips project within its
// tolerance.
ActorChoice ChooseActor(const std::vector<Camera>& cameras,
                        const std::vector<std::vector<HipSighting>>& candidates,
                        const std::vector<std::optional<HipSighting>>& known);

}  // namespace fvv

#endif  // FVV_ENCODER_TRACK_PERSON_SELECTION_H_
