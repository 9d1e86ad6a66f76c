// Shape refinement: the generic body model's vertices
// moved to the actor's true surface by gradient descent, coarse to fine,
// in the pose of one or more captured frames, then carried back to the bind
// pose through the inverse of each vertex's skinning transform, so the refined
// mesh keeps its skinning, atlas and topology. Per vertex the descent weighs:
//
// - silhouette: the distance to the visual hull's surface. A vertex outside
//   the hull is pulled onto it (the actor lies inside the hull); one inside is
//   pulled out only where it lies on a camera's contour (normal nearly
//   perpendicular to the camera's ray, seen by it), where the true surface
//   touches the hull. Elsewhere the hull bulges past concave surfaces and says
//   nothing.
// - model-based stereo: a key view (the camera facing the vertex best, where
//   it sees it) and the adjacent cameras that see it; the vertex slides along
//   the key camera's ray (the epipolar line in the adjacent views) within the
//   search range of the current level, matching a patch laid on the model's
//   tangent plane by normalised cross-correlation (so foreshortening between
//   the views is undone by the model, as rectification would for a plane).
//   Occluded views are excluded by a depth-map visibility test of the current
//   shape.
// - features (when given): the errors between the model's joint centres and
//   the reconstructed feature points, interpolated to every vertex by a
//   thin-plate radial basis function (biharmonic in 3D, |r|, with an affine
//   part), move the surface with the joints it should follow, once, before
//   the descent.
// - regularisation: each vertex kept near its position reconstructed from its
//   neighbouring triangles' local frames (barycentric coordinates in the plane
//   of three 1-ring neighbours plus a height along its normal, scaled with the
//   triangle), which holds the mesh's parameterisation, and so its skinning
//   and atlas, while the surface moves.
//
// The data terms' displacements are smoothed over the mesh before each step,
// more at coarse levels (large search ranges move whole regions) and less at
// fine ones.
#ifndef FVV_ENCODER_SHAPE_SHAPE_REFINEMENT_H_
#define FVV_ENCODER_SHAPE_SHAPE_REFINEMENT_H_

#include <Eigen/Core>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "codec/base/parallel.h"
#include "codec/base/status.h"
#include "container/body_model.h"
#include "container/cameras.h"
#include "encoder/io/image_io.h"
#include "encoder/shape/visual_hull.h"

namespace fvv {

struct ShapeRefinementOptions {
  // The model's expected error per level, coarse to fine (metres): the stereo
  // search range and the reach of the silhouette term.
  std::vector<double> levels = {0.04, 0.02, 0.01};
  int iterations = 12;  // descent steps per level
  double step = 0.5;    // share of the weighted displacement taken per step
  double silhouette_weight = 1.0;
  double stereo_weight = 0.3;
  double regularisation_weight = 1.0;
  double feature_weight = 1.0;   // share of the interpolated feature errors applied
  double min_ncc = 0.8;          // weaker stereo matches are not used
  double min_patch_std = 3.0;    // a key patch flatter than this (8-bit levels) has no stereo
  int patch_radius = 2;          // the stereo patch is (2r + 1)^2 samples
  double contour_cosine = 0.35;  // |normal . ray| below this: on that camera's contour
  VisualHullOptions hull;
};

// One captured frame: the pose (generic-body DOFs), and per camera its RGB
// image and silhouette (grey, non-zero = actor).
struct RefinementFrame {
  std::vector<double> dofs;
  std::vector<Image> images, silhouettes;
  // Optional: reconstructed 3D feature points (joint centres by generic joint
  // name, e.g. TriangulateFeatures' positions).
  std::map<std::string, Eigen::Vector3d> features;
};

struct ShapeRefinementReport {
  struct Level {
    double range = 0;
    size_t stereo_matches = 0;    // vertices with an accepted stereo target (summed over frames)
    size_t contour_vertices = 0;  // pulled to the hull from inside
    size_t outside_hull = 0;      // outside the hull at the level's start
    double mean_move = 0;         // metres, over the level, mean over vertices (those kept)
    size_t dropped = 0;           // frames whose level diverged and was undone
  };
  std::vector<Level> levels;
  double seconds = 0;
};

// The refined model (same skeleton, topology, atlas and skinning; positions
// and normals changed). Frames' refined shapes are averaged in the bind pose.
StatusOr<BodyModel> RefineShape(const BodyModel& model, const std::vector<Camera>& cameras,
                                const std::vector<RefinementFrame>& frames,
                                const ShapeRefinementOptions& options,
                                ShapeRefinementReport* report = nullptr,
                                const ParallelRunner& runner = SerialRunner,
                                const std::function<void(const std::string&)>& progress = {});

// The refined shape of one frame in its pose (what RefineShape averages),
// for measuring against a known surface. `posed` receives every vertex.
Status RefinePosedShape(const BodyModel& model, const std::vector<Camera>& cameras,
                        const RefinementFrame& frame, const ShapeRefinementOptions& options,
                        std::vector<Eigen::Vector3f>* posed,
                        ShapeRefinementReport* report = nullptr,
                        const ParallelRunner& runner = SerialRunner);

}  // namespace fvv

#endif  // FVV_ENCODER_SHAPE_SHAPE_REFINEMENT_H_
