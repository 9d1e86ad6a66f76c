// How far the silhouettes tracking read agree with the true ones `fvv synth`
// writes (truth/silhouettes/<camera>/NNNNNN.png, the actor alone): what the
// masks themselves allow a fit, before any tracking error.
#ifndef FVV_ENCODER_TRACK_SILHOUETTE_TRUTH_H_
#define FVV_ENCODER_TRACK_SILHOUETTE_TRUTH_H_

#include <string>
#include <vector>

#include "codec/base/status.h"

namespace fvv {

struct SilhouetteAgreement {
  std::vector<std::string> cameras;
  std::vector<double> iou;  // per camera, the mean over the frames
  double mean = 0;          // over cameras and frames
  uint32_t frames = 0;
};

// `truth`: fvv synth's output directory or its truth/ directory. `saved`: a
// directory of silhouettes as `fvv track --save-silhouettes` writes them
// (<camera>_NNNNNN.png), for frames `first`..`last`. A file missing on either
// side, or of another size, is an error naming it.
StatusOr<SilhouetteAgreement> CompareSilhouettesWithTruth(const std::string& truth,
                                                          const std::string& saved,
                                                          const std::vector<std::string>& cameras,
                                                          uint32_t first, uint32_t last);

}  // namespace fvv

#endif  // FVV_ENCODER_TRACK_SILHOUETTE_TRUTH_H_
