// Whole-frame offsets between cameras from the tangents of their silhouettes:
// cameras out of step by a frame see the actor's moving limbs where the
// others saw them a frame before or after, and no turn of the cameras makes
// those tangents agree. Each candidate offset of each camera is scored by
// how well the tangents agree once the cameras are turned to fit them
// (tangent_calibration.h), one camera at a time against the rest, until no
// offset changes. The keypoint sync (camera_sync.h) places the network's
// joints, which are noisy enough to leave a camera a frame off; this needs
// a calibration good to a few pixels, so it refines what that found.
#ifndef FVV_ENCODER_TRACK_TANGENT_SYNC_H_
#define FVV_ENCODER_TRACK_TANGENT_SYNC_H_

#include <functional>
#include <string>
#include <vector>

#include "codec/base/status.h"
#include "container/cameras.h"
#include "encoder/track/outline_hull.h"
#include "encoder/track/tangent_calibration.h"

namespace fvv {

struct TangentSyncOptions {
  int range = 2;  // frames either way of each camera's present offset
  TangentCalibrationOptions refine;
  std::function<void(const std::string&)> progress;
};

struct TangentSync {
  // Per camera, frames to add to its present offset, the smallest 0.
  std::vector<int> offsets;
  // The tangents' mean cost (TangentCalibration::mean_cost) as the cameras
  // ran, and at the offsets found.
  double cost_before = 0, cost_after = 0;
  int evaluations = 0;  // refinements run
};

// `outlines[camera][k]`: the hull of frame `k - range` of the span compared,
// k from 0 to span + 2 range - 1 (the span and `range` frames either side).
StatusOr<TangentSync> SyncFromTangents(const std::vector<Camera>& cameras,
                                       const std::vector<std::vector<OutlineHull>>& outlines,
                                       const TangentSyncOptions& options = {});

}  // namespace fvv

#endif  // FVV_ENCODER_TRACK_TANGENT_SYNC_H_
