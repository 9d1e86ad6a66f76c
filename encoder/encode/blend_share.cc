#include "encoder/encode/blend_share.h"

#include <algorithm>
#include <cmath>

#include "container/geometric_visibility.h"

namespace fvv {
namespace {

// The blend weight without the viewing-angle term.
double FacingWeight(double facing) {
  namespace gv = geometric_visibility;
  if (!(facing > gv::kMinFacing)) return 0;
  return gv::FacingRamp(facing) * std::pow(std::max(facing, 1e-3), gv::kFacingExponent);
}

}  // namespace

double LargestBlendShare(uint32_t c, uint32_t n, const Eigen::Vector3f* to_camera,
                         const double* facing, const uint8_t* takes) {
  namespace gv = geometric_visibility;
  const double own = FacingWeight(facing[c]);
  if (!(own > 0)) return 0;
  double total = own;
  for (uint32_t k = 0; k < n; ++k) {
    if (k == c || !takes[k]) continue;
    const double angle = std::acos(std::clamp(double(to_camera[c].dot(to_camera[k])), -1.0, 1.0));
    total += std::pow(gv::kAngleEpsilon / (angle + gv::kAngleEpsilon), gv::kViewExponent) *
             FacingWeight(facing[k]);
  }
  return own / total;
}

}  // namespace fvv
