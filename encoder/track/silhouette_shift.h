// The one image shift, the same in every frame, that best lays a camera's
// fitted silhouettes on its masks. A camera whose calibration disagrees with
// the others' by a small turn sees the fitted model beside the actor by the
// same few pixels in every frame, whatever the pose; a fit that is wrong
// differs from frame to frame. So the shift tells the calibration's share of
// a camera's misfit apart from the tracking's (docs/tracking.md).
#ifndef FVV_ENCODER_TRACK_SILHOUETTE_SHIFT_H_
#define FVV_ENCODER_TRACK_SILHOUETTE_SHIFT_H_

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "encoder/io/image_io.h"

namespace fvv {

// The IoU of the 0/non-0 mask `moved`, moved by (dx, dy) pixels (what falls
// outside the image is dropped), against `fixed`; 1 when both are empty.
double ShiftedMaskIou(const Image& moved, const Image& fixed, int dx, int dy);

struct SilhouetteShift {
  Eigen::Vector2d pixels = Eigen::Vector2d::Zero();  // move the silhouettes by this
  double iou = 0;                                    // mean IoU over the frames, unshifted
  double shifted_iou = 0;  // the same at the best shift (both on the search's grid)
  int frames = 0;
};

// Adds frames one at a time (a fit's silhouette and the mask it is scored
// against, the same size) and finds the shift within `range` pixels that
// gives the highest mean IoU over all of them; `range` 0: a 40th of the
// image's longer side (48 pixels at 1080x1920, about 1.5 degrees of turn for
// the usual lenses). The search runs on masks reduced so that the range is
// 12 grid steps (by 4 for 48 pixels), the peak placed between grid points by
// a parabola: the shift is good to a pixel or two, and a frame costs a few
// milliseconds at any size. A shift at the range's edge is clipped there.
class SilhouetteShiftSearch {
 public:
  explicit SilhouetteShiftSearch(int range = 0);
  void Add(const Image& silhouette, const Image& mask);
  SilhouetteShift Best() const;

 private:
  int range_;                 // pixels; 0: from the first frame's size
  int reduction_ = 1;         // set by the first frame
  int cells_ = 0;             // the grid's half width, in reduced pixels
  std::vector<double> sums_;  // per grid shift, the IoU summed over frames
  int frames_ = 0;
};

}  // namespace fvv

#endif  // FVV_ENCODER_TRACK_SILHOUETTE_SHIFT_H_
