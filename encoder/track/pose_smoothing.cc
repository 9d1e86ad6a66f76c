#include "encoder/track/pose_smoothing.h"

#include <algorithm>
#include <cmath>

namespace fvv {

int PoseSmoothing::Radius() const {
  if (!(sigma_frames > 0)) return 0;
  // 2.5 sigma: the weight left out beyond it is under 1.3 %.
  return int(std::ceil(2.5 * std::min(sigma_frames, 16.0)));
}

std::vector<double> SmoothPose(const std::vector<std::vector<double>>& poses,
                               const std::vector<bool>& trusted, const std::vector<bool>& angular,
                               size_t centre, const PoseSmoothing& smoothing) {
  const std::vector<double>& c = poses[centre];
  const int r = smoothing.Radius();
  if (r == 0) return c;
  const double kPi = 3.14159265358979323846;
  std::vector<double> sum(c.size(), 0.0);
  double weights = 0;
  const size_t lo = centre >= size_t(r) ? centre - r : 0;
  const size_t hi = std::min(poses.size() - 1, centre + size_t(r));
  for (size_t i = lo; i <= hi; ++i) {
    if (i != centre && i < trusted.size() && !trusted[i]) continue;
    if (poses[i].size() != c.size()) continue;
    const double k = (double(i) - double(centre)) / smoothing.sigma_frames;
    const double w = std::exp(-0.5 * k * k);
    for (size_t d = 0; d < c.size(); ++d) {
      double v = poses[i][d];
      if (d < angular.size() && angular[d]) v = c[d] + std::remainder(v - c[d], 2 * kPi);
      sum[d] += w * v;
    }
    weights += w;
  }
  for (double& v : sum) v /= weights;
  return sum;
}

}  // namespace fvv
