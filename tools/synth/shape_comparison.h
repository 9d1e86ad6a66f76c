// Shape refinement measured against a synthetic capture's known geometry
//: for one frame, the generic model (true pose and
// proportions), the visual hull and the refined model are compared with the
// actor's true surface (mean and 95th-percentile distances, both ways: from
// the true surface the cameras see to each shape, and from each shape's seen
// surface to the truth), and each is drawn by Renderer I from the capture's
// held-out cameras and scored against the generator's own render of them
// (RGB PSNR over the actor's pixels) -- the comparison the original system's
// paper makes. One table from one run, for the test and the benchmark.
#ifndef FVV_TOOLS_SYNTH_SHAPE_COMPARISON_H_
#define FVV_TOOLS_SYNTH_SHAPE_COMPARISON_H_

#include <string>
#include <vector>

#include "codec/base/status.h"
#include "encoder/shape/shape_refinement.h"
#include "encoder/shape/surface_index.h"
#include "tools/synth/synth.h"

namespace fvv {

struct ShapeScore {
  std::string name;
  DistanceSummary from_truth;  // true seen surface -> this shape
  DistanceSummary to_truth;    // this shape's seen surface -> the true surface
  double novel_view_psnr = 0;  // mean over the held-out cameras
};

struct ShapeComparison {
  std::vector<ShapeScore> shapes;  // generic, visual hull, refined
  ShapeRefinementReport refinement;
  // The table as text, one row per shape.
  std::string Table() const;
};

struct ComparisonOptions {
  // Refine with the capture's feature points (truth/features.json,
  // triangulated) as the features term.
  bool features = false;
  // Start from a pose this far off (metres, the root moved along x; the
  // lumbar bent by 5 radians per metre): a tracker's error.
  double pose_error = 0;
};

// `synth` made the capture in synth.output_dir (with held-out cameras); it is
// made again here in memory to know the true surface. Silhouettes are the
// capture's true ones when it lists them, else extracted.
StatusOr<ShapeComparison> CompareShapes(const SynthOptions& synth, uint32_t frame,
                                        const ShapeRefinementOptions& options,
                                        const ComparisonOptions& comparison = {});

}  // namespace fvv

#endif  // FVV_TOOLS_SYNTH_SHAPE_COMPARISON_H_
