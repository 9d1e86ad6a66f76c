// Silhouettes by background subtraction: per-pixel background colour
// from the capture's plates (or the temporal median of its frames when it has
// none), a brightness / chroma-distortion test that keeps cast shadows and
// highlights in the background, then morphology and connected components.
#ifndef FVV_ENCODER_TRACK_SILHOUETTE_H_
#define FVV_ENCODER_TRACK_SILHOUETTE_H_

#include <vector>

#include "codec/base/status.h"
#include "encoder/io/image_io.h"

namespace fvv {

struct SilhouetteParams {
  double min_difference = 18;     // |I - B| (summed RGB levels) below this: background
  double chroma = 8;              // chroma distortion (8-bit levels) above this: foreground
  double chroma_relative = 0.07;  // ... plus this fraction of the expected brightness alpha |B|
  double shadow_low = 0.45;       // brightness ratio I/B in [shadow_low, highlight_high] with
  double highlight_high = 1.25;   //   little chroma change: shadow or highlight, background
  double min_component = 0.0004;  // components smaller than this share of the image are dropped
  double keep_relative = 0.02;    // ... and those below this share of the largest component
};

// Per-pixel background colour of one camera (RGB).
struct BackgroundModel {
  Image colour;
};

// The temporal median of `frames` (same size, RGB): a background estimate when
// the actor moves enough that each pixel is empty in most frames.
Image TemporalMedian(const std::vector<Image>& frames);

// 0/255 grey silhouette of `frame` against `background`.
StatusOr<Image> ExtractSilhouette(const Image& frame, const BackgroundModel& background,
                                  const SilhouetteParams& params = SilhouetteParams());

// Morphology and components, exposed for tests: 3x3 open then close, drop
// small components, fill holes that do not touch the border.
void CleanMask(Image* mask, const SilhouetteParams& params);

// A coarse mask (the person network's, 0/non-0) refined at full resolution
// along its edge by a fine one (background subtraction's): within `radius`
// pixels of the coarse edge the fine mask decides; deeper inside the coarse
// mask holds (a shirt the colour of the wall behind), further out is
// background (a chair that moved). 0/255 out.
void RefineMaskEdges(Image* coarse, const Image& fine, int radius);

// |A xor B| / |A or B| style figures of two 0/non-0 masks.
double MaskIou(const Image& a, const Image& b);

}  // namespace fvv

#endif  // FVV_ENCODER_TRACK_SILHOUETTE_H_
