#include "encoder/track/outline_hull.h"

#include <algorithm>

#include "encoder/capture/calibration.h"

namespace fvv {
namespace {

double Cross(const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

struct HullPoint {
  Eigen::Vector2d p;
  uint8_t border;
};

}  // namespace

OutlineHull MakeOutlineHull(const Camera& camera, const Image& mask, int border_px) {
  OutlineHull hull;
  const int w = int(mask.width), h = int(mask.height), ch = mask.channels;
  if (w == 0 || h == 0 || mask.pixels.size() < size_t(w) * size_t(h) * size_t(ch)) return hull;
  // A hull vertex is the leftmost or rightmost pixel of its row (or of the top
  // or bottom row, which the row's ends cover too), so only those are
  // undistorted: four corners each, the square the pixel covers.
  std::vector<HullPoint> candidates;
  for (int y = 0; y < h; ++y) {
    const uint8_t* row = &mask.pixels[size_t(y) * size_t(w) * size_t(ch)];
    int lo = -1, hi = -1;
    for (int x = 0; x < w; ++x) {
      if (row[size_t(x) * size_t(ch)] != 0) {
        if (lo < 0) lo = x;
        hi = x;
      }
    }
    if (lo < 0) continue;
    for (int x : {lo, hi}) {
      const uint8_t border =
          x < border_px || x >= w - border_px || y < border_px || y >= h - border_px;
      for (double dx : {-0.5, 0.5}) {
        for (double dy : {-0.5, 0.5}) {
          const Eigen::Vector2d normalised((x + dx - camera.cx) / camera.fx,
                                           (y + dy - camera.cy) / camera.fy);
          candidates.push_back({Undistort(camera, normalised), border});
        }
      }
      if (lo == hi) break;
    }
  }
  if (candidates.size() < 3) return hull;
  // Andrew's monotone chain.
  std::sort(candidates.begin(), candidates.end(), [](const HullPoint& a, const HullPoint& b) {
    return a.p.x() < b.p.x() || (a.p.x() == b.p.x() && a.p.y() < b.p.y());
  });
  std::vector<HullPoint> chain(2 * candidates.size());
  size_t k = 0;
  for (size_t i = 0; i < candidates.size(); ++i) {
    while (k >= 2 && Cross(chain[k - 2].p, chain[k - 1].p, candidates[i].p) <= 0) --k;
    chain[k++] = candidates[i];
  }
  for (size_t i = candidates.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && Cross(chain[k - 2].p, chain[k - 1].p, candidates[i].p) <= 0) --k;
    chain[k++] = candidates[i];
  }
  chain.resize(k - 1);  // the last point is the first again
  for (const HullPoint& c : chain) {
    hull.points.push_back(c.p);
    hull.at_border.push_back(c.border);
  }
  return hull;
}

bool InsideOutlineHull(const OutlineHull& hull, const Eigen::Vector2d& p) {
  if (hull.points.size() < 3) return false;
  for (size_t i = 0; i < hull.points.size(); ++i) {
    const Eigen::Vector2d& a = hull.points[i];
    const Eigen::Vector2d& b = hull.points[(i + 1) % hull.points.size()];
    if (Cross(a, b, p) < 0) return false;
  }
  return true;
}

}  // namespace fvv
