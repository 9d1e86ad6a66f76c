#include "encoder/track/tangent_sync.h"

#include <algorithm>
#include <cstdio>
#include <map>

namespace fvv {

StatusOr<TangentSync> SyncFromTangents(const std::vector<Camera>& cameras,
                                       const std::vector<std::vector<OutlineHull>>& outlines,
                                       const TangentSyncOptions& o) {
  const size_t n = cameras.size();
  if (n < 2) return InvalidArgument("sync: tangents need 2 cameras or more");
  if (outlines.size() != n) return InvalidArgument("sync: one list of outlines per camera");
  if (o.range < 1) return InvalidArgument("sync: the offset range must be a frame or more");
  const size_t frames = outlines[0].size();
  for (const auto& c : outlines) {
    if (c.size() != frames) return InvalidArgument("sync: every camera's outlines of one span");
  }
  if (frames < size_t(2 * o.range + 3)) {
    return InvalidArgument("sync: a span of 3 frames or more is needed besides the range");
  }
  const size_t span = frames - size_t(2 * o.range);
  // The cost of the cameras at offsets `at` (each within the range), each
  // set of offsets refined once: a later pass tries many of them again.
  TangentSync result;
  std::map<std::vector<int>, StatusOr<double>> tried;
  auto cost = [&](const std::vector<int>& at) -> StatusOr<double> {
    if (auto it = tried.find(at); it != tried.end()) return it->second;
    std::vector<std::vector<OutlineHull>> by_frame(span, std::vector<OutlineHull>(n));
    for (size_t f = 0; f < span; ++f) {
      for (size_t c = 0; c < n; ++c) by_frame[f][c] = outlines[c][size_t(int(f) + o.range + at[c])];
    }
    ++result.evaluations;
    StatusOr<TangentCalibration> r = RefineCamerasFromTangents(cameras, by_frame, o.refine);
    StatusOr<double> c = r.ok() ? StatusOr<double>(r->mean_cost) : StatusOr<double>(r.status());
    tried.emplace(at, c);
    return c;
  };
  std::vector<int> at(n, 0);
  FVV_ASSIGN_OR_RETURN(result.cost_before, cost(at));
  double best = result.cost_before;
  // Every camera moves in turn, the first too (a first camera out of step with
  // the rest is found only so); only differences between offsets count.
  for (int pass = 0; pass < 4; ++pass) {
    bool changed = false;
    for (size_t c = 0; c < n; ++c) {
      int best_d = at[c];
      for (int d = -o.range; d <= o.range; ++d) {
        if (d == at[c]) continue;
        std::vector<int> trial = at;
        trial[c] = d;
        // An offset at which the tangents would turn a camera too far is not it.
        StatusOr<double> v = cost(trial);
        if (v.ok() && *v < best) best = *v, best_d = d;
      }
      changed = changed || best_d != at[c];
      at[c] = best_d;
      if (o.progress) {
        char line[128];
        std::snprintf(line, sizeof(line), "sync: pass %d, %s at %+d frames (cost %.3f)", pass + 1,
                      cameras[c].name.c_str(), at[c], best);
        o.progress(line);
      }
    }
    if (!changed) break;
  }
  result.cost_after = best;
  const int lowest = *std::min_element(at.begin(), at.end());
  for (int& a : at) a -= lowest;
  result.offsets = at;
  return result;
}

}  // namespace fvv
