// Retargeting BVH motion (e.g. the CMU database) onto the generic body model:
// each generic bone follows a corresponding BVH bone's world orientation,
// corrected by the rotation between the two skeletons' rest directions, then
// expressed in the generic bone's Euler DOFs (components it lacks dropped) and
// clamped to its limits. The root's path is scaled by the ratio of leg
// lengths, centred on the capture volume, and the feet put on the floor.
#ifndef FVV_ENCODER_IMPORT_RETARGET_H_
#define FVV_ENCODER_IMPORT_RETARGET_H_

#include <vector>

#include "codec/base/status.h"
#include "container/body_model.h"
#include "encoder/import/bvh.h"

namespace fvv {

struct RetargetOptions {
  double fps = 25;
  uint32_t frames = 0;  // 0: as many as the clip holds from `start_seconds`
  double start_seconds = 0;
  bool centre = true;  // move the clip's mean horizontal position to the origin
};

// One DOF vector per output frame for the generic body's skeleton. Errors name
// the generic joint a BVH skeleton has no counterpart for, or a clip too short.
StatusOr<std::vector<std::vector<double>>> RetargetToGenericBody(const BvhMotion& bvh,
                                                                 const Skeleton& generic,
                                                                 const RetargetOptions& options);

}  // namespace fvv

#endif  // FVV_ENCODER_IMPORT_RETARGET_H_
