#include "encoder/encode/blend_share.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "container/geometric_visibility.h"

namespace fvv {
double BlendFacingWeight(double facing) {
  namespace gv = geometric_visibility;
  if (!(facing > gv::kMinFacing)) return 0;
  return gv::FacingRamp(facing) * std::pow(std::max(facing, 1e-3), gv::kFacingExponent);
}

double LargestBlendShareOfWeights(uint32_t c, uint32_t n, const Eigen::Vector3f* to_camera,
                                  const double* weight, const uint8_t* takes) {
  namespace gv = geometric_visibility;
  static_assert(gv::kViewExponent == 4.0, "the angle term below is a fourth power");
  const double own = weight[c];
  if (!(own > 0)) return 0;
  double total = own;
  for (uint32_t k = 0; k < n; ++k) {
    // A camera facing away weighs nothing: its angle is not worth working out
    // (a dome's cameras make this a loop over every camera per texel).
    if (k == c || !takes[k] || weight[k] == 0) continue;
    const double angle = std::acos(std::clamp(double(to_camera[c].dot(to_camera[k])), -1.0, 1.0));
    const double r = gv::kAngleEpsilon / (angle + gv::kAngleEpsilon), r2 = r * r;
    total += r2 * r2 * weight[k];
  }
  return own / total;
}

double LargestBlendShare(uint32_t c, uint32_t n, const Eigen::Vector3f* to_camera,
                         const double* facing, const uint8_t* takes) {
  std::vector<double> weight(n);
  for (uint32_t k = 0; k < n; ++k) weight[k] = BlendFacingWeight(facing[k]);
  return LargestBlendShareOfWeights(c, n, to_camera, weight.data(), takes);
}

}  // namespace fvv
