#include "encoder/track/silhouette_shift.h"

#include <algorithm>
#include <cmath>

namespace fvv {
namespace {

// The search grid's half width, in grid steps: the masks are reduced so the
// range fits in it, and a frame costs a few milliseconds at any size.
constexpr int kCells = 12;

// A 0/non-0 mask at 1/f of its size: a cell is set where at least half its
// pixels are (the remainder rows and columns are dropped).
Image Reduced(const Image& im, int f) {
  if (f == 1) return im;
  Image r;
  r.width = im.width / f, r.height = im.height / f, r.channels = 1;
  r.pixels.assign(size_t{r.width} * r.height, 0);
  for (uint32_t y = 0; y < r.height; ++y) {
    for (uint32_t x = 0; x < r.width; ++x) {
      int on = 0;
      for (int j = 0; j < f; ++j) {
        const uint8_t* row = &im.pixels[(size_t(y) * f + j) * im.width + size_t(x) * f];
        for (int i = 0; i < f; ++i) on += row[i] != 0;
      }
      r.pixels[size_t(y) * r.width + x] = 2 * on >= f * f ? 255 : 0;
    }
  }
  return r;
}

size_t Count(const Image& im) {
  return size_t(std::count_if(im.pixels.begin(), im.pixels.end(), [](uint8_t v) { return v; }));
}

// Where the peak of three samples lies between them, in [-0.5, 0.5].
double ParabolaPeak(double before, double at, double after) {
  const double curvature = before - 2 * at + after;
  if (curvature >= 0) return 0;
  return std::clamp(0.5 * (before - after) / curvature, -0.5, 0.5);
}

}  // namespace

double ShiftedMaskIou(const Image& moved, const Image& fixed, int dx, int dy) {
  const int w = int(fixed.width), h = int(fixed.height);
  size_t inter = 0;
  for (int y = 0; y < h; ++y) {
    const int sy = y - dy;
    if (sy < 0 || sy >= h) continue;
    for (int x = 0; x < w; ++x) {
      const int sx = x - dx;
      if (sx < 0 || sx >= w) continue;
      inter += fixed.pixels[size_t(y) * w + x] && moved.pixels[size_t(sy) * w + sx];
    }
  }
  // What the move takes out of the image still counts as missing.
  const size_t uni = Count(moved) + Count(fixed) - inter;
  return uni ? double(inter) / double(uni) : 1.0;
}

SilhouetteShiftSearch::SilhouetteShiftSearch(int range) : range_(range) {}

void SilhouetteShiftSearch::Add(const Image& silhouette, const Image& mask) {
  if (frames_ == 0) {
    // The first frame sets the grid: the later ones are the same camera's.
    const int range =
        range_ > 0 ? range_ : std::max(1, int(std::max(mask.width, mask.height) / 40));
    reduction_ = (range + kCells - 1) / kCells;
    cells_ = std::max(1, range / reduction_);
    sums_.assign(size_t(2 * cells_ + 1) * (2 * cells_ + 1), 0.0);
  }
  const Image a = Reduced(silhouette, reduction_), b = Reduced(mask, reduction_);
  const int w = int(b.width), h = int(b.height), side = 2 * cells_ + 1;
  const size_t count_a = Count(a), count_b = Count(b);
  std::vector<int> set;  // the mask's cells, as y * w + x
  set.reserve(count_b);
  for (int i = 0; i < w * h; ++i) {
    if (b.pixels[size_t(i)]) set.push_back(i);
  }
  std::vector<size_t> inter(sums_.size(), 0);
  for (int i : set) {
    const int x = i % w, y = i / w;
    for (int dy = -cells_; dy <= cells_; ++dy) {
      const int sy = y - dy;
      if (sy < 0 || sy >= h) continue;
      const uint8_t* row = &a.pixels[size_t(sy) * w];
      size_t* out = &inter[size_t(dy + cells_) * side];
      for (int dx = -cells_; dx <= cells_; ++dx) {
        const int sx = x - dx;
        if (sx >= 0 && sx < w && row[sx]) ++out[dx + cells_];
      }
    }
  }
  for (size_t k = 0; k < sums_.size(); ++k) {
    const size_t uni = count_a + count_b - inter[k];
    sums_[k] += uni ? double(inter[k]) / double(uni) : 1.0;
  }
  ++frames_;
}

SilhouetteShift SilhouetteShiftSearch::Best() const {
  SilhouetteShift s;
  s.frames = frames_;
  if (frames_ == 0) return s;
  const int side = 2 * cells_ + 1;
  const size_t best = size_t(std::max_element(sums_.begin(), sums_.end()) - sums_.begin());
  const int bx = int(best % side), by = int(best / side);
  auto at = [&](int x, int y) { return sums_[size_t(y) * side + x]; };
  double fx = 0, fy = 0;
  if (bx > 0 && bx < side - 1) fx = ParabolaPeak(at(bx - 1, by), at(bx, by), at(bx + 1, by));
  if (by > 0 && by < side - 1) fy = ParabolaPeak(at(bx, by - 1), at(bx, by), at(bx, by + 1));
  s.pixels = Eigen::Vector2d(bx - cells_ + fx, by - cells_ + fy) * reduction_;
  s.iou = at(cells_, cells_) / frames_;
  s.shifted_iou = sums_[best] / frames_;
  return s;
}

}  // namespace fvv
