// BVH motion files (Biovision hierarchy; the CMU motion-capture database is
// distributed in it): skeleton and per-frame channel values, as an fvv Skeleton
// and DOF vectors. Retargeting onto the generic body model builds on this.
#ifndef FVV_ENCODER_IMPORT_BVH_H_
#define FVV_ENCODER_IMPORT_BVH_H_

#include <string>
#include <vector>

#include "codec/base/status.h"
#include "container/body_model.h"

namespace fvv {

struct BvhMotion {
  Skeleton skeleton;      // one bone per ROOT/JOINT (End Sites dropped), DOFs from CHANNELS
  double frame_time = 0;  // seconds
  // Per frame, one value per Skeleton::Dofs() entry: radians, metres.
  std::vector<std::vector<double>> frames;
};

// unit_metres: the length of one BVH unit (0.01 for centimetres; CMU files use
// 1/0.45 inch = 0.056444 m). Rotation channels are unwrapped over time (no
// jumps of 360 degrees), so values stay continuous for prediction and resampling.
StatusOr<BvhMotion> ParseBvh(const std::string& text, double unit_metres);
StatusOr<BvhMotion> ReadBvhFile(const std::string& path, double unit_metres);

// Resamples to `fps`, starting `start_seconds` into the clip, by linear
// interpolation between the two nearest frames.
std::vector<std::vector<double>> ResampleMotion(const BvhMotion& motion, double fps,
                                                double start_seconds = 0);

}  // namespace fvv

#endif  // FVV_ENCODER_IMPORT_BVH_H_
