// The surface of every frame: the posed body model moved along its normals,
// frame after frame, until its outline agrees with each camera's silhouette
// (what a stream carries with the surface tool, SPEC.md 3.5.2). Fast enough
// for every frame of a take: it works on the silhouettes at about 640 pixels,
// starts from the previous frame's surface and takes a few steps.
//
// Per vertex and step, the data terms are image distances turned into moves
// along the normal (a move of d metres shifts the vertex's image by d times
// the normal's part across the ray, times the focal length over depth):
//
// - a vertex whose image lies outside a camera's silhouette comes in by its
//   distance to the silhouette (the actor lies inside every silhouette's
//   cone); the camera that asks for most wins;
// - elsewhere, a vertex on a camera's contour (normal nearly across the ray,
//   nothing of the model beyond it in that image) goes out to the
//   silhouette's outline, searched along the normal's image direction; the
//   contour cameras' moves are averaged;
// - with the camera images given and stereo on (by the options, or where
//   the rig suits it), a vertex no silhouette speaks for (facing the
//   cameras) goes where a patch on its surface matches between the camera
//   facing it best and its neighbours (patch_stereo.h), weighted by the
//   match's correlation.
//
// The moves are spread over the mesh (neighbours' weighted moves), then each
// vertex's displacement is pulled towards them, towards its neighbours' mean
// (smoothness), its previous frame's (time) and zero (the fitted body's
// shape), so clothing and hair that the skeleton does not carry are followed
// and nothing else is bought.
#ifndef FVV_ENCODER_SHAPE_SURFACE_TRACKING_H_
#define FVV_ENCODER_SHAPE_SURFACE_TRACKING_H_

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "codec/base/parallel.h"
#include "codec/base/status.h"
#include "container/body_model.h"
#include "container/cameras.h"
#include "encoder/body/kinematics.h"
#include "encoder/io/image_io.h"
#include "encoder/shape/patch_stereo.h"

namespace fvv {

struct SurfaceTrackingOptions {
  int max_side = 640;              // silhouettes are worked at about this size (longer side)
  int steps = 8;                   // per frame (three times as many on the first)
  double step = 0.6;               // share of the way to the weighted target taken per step
  double reach = 0.06;             // metres: the outline is searched this far along the normal
  double max_displacement = 0.08;  // metres, either way
  double contour_cosine = 0.35;    // |normal . ray| below this: on that camera's contour
  // |normal . ray| below this: a vertex outside the silhouette comes in (one
  // facing the camera moves its image little along its normal, and its
  // neighbours nearer the contour bring it in).
  double outside_cosine = 0.6;
  int spread = 8;           // passes spreading the data terms to neighbours
  double smoothness = 1.0;  // pull towards the neighbours' mean displacement
  double prior = 0.3;       // pull towards the fitted body (zero)
  // Pull towards the previous frame's displacement, and the weight of a
  // stereo match (times its correlation) against a silhouette term's 1 (0:
  // silhouettes alone; matched every `stereo_every` steps). Below zero: by
  // the rig, on the first frame (RigSuitsStereo): where it suits stereo,
  // kStereoRigSurfaceStereo and, with stereo on, kStereoRigSurfaceTemporal; elsewhere no
  // stereo and kSurfaceTemporal.
  double temporal = -1;
  double stereo = -1;
  int stereo_every = 4;
  PatchStereoOptions stereo_match;
  // Metres a pixel at working size may cover at the actor for the rig to
  // suit stereo: a match is good to about a pixel over the cameras' angle,
  // and coarser than the silhouettes' surface it only adds noise.
  double stereo_max_pixel = 0.008;
};

// The weights chosen by the rig (SurfaceTrackingOptions::temporal, stereo).
constexpr double kSurfaceTemporal = 1.0;
constexpr double kStereoRigSurfaceStereo = 10.0;
constexpr double kStereoRigSurfaceTemporal = 0.0;

// Whether the rig filming an actor at `actor` suits stereo: seen from the
// actor, every camera has options.stereo_match.min_neighbours others within
// its max_angle, and a pixel at working size covers at most
// options.stereo_max_pixel there.
bool RigSuitsStereo(const std::vector<Camera>& cameras, const Eigen::Vector3d& actor,
                    const SurfaceTrackingOptions& options);

struct SurfaceTrackingReport {
  double outside = 0;   // share of the vertex sightings outside a silhouette, at the last step
  double contour = 0;   // share of vertices on some camera's contour, at the last step
  double mean_abs = 0;  // metres, mean |displacement|
  double stereo = 0;    // share of vertices with a stereo match, at the last match
  // The weights used (SurfaceTrackingOptions' own, or chosen by the rig).
  double temporal_weight = 0, stereo_weight = 0;
};

class SurfaceTracker {
 public:
  // `mesh`: the body model's (bind pose, its normals).
  SurfaceTracker(const Mesh& mesh, const SurfaceTrackingOptions& options);

  // The frame posed by `skinning` (SkinningMatrices), seen by `cameras` with
  // silhouettes (grey, non-zero = actor; an empty image: that camera is not
  // used) and, for the stereo term, `images` (RGB, one per camera; empty:
  // none). Returns each vertex's displacement along its bind-pose normal in
  // metres (welded copies equal), and remembers it for the next frame.
  StatusOr<std::vector<float>> Track(const std::vector<Affine>& skinning,
                                     const std::vector<Camera>& cameras,
                                     const std::vector<Image>& silhouettes,
                                     const std::vector<Image>& images,
                                     SurfaceTrackingReport* report = nullptr,
                                     const ParallelRunner& runner = SerialRunner);

  // Forgets the previous frame (a cut in the take).
  void Reset() {
    previous_.assign(previous_.size(), 0.0f);
    started_ = false;
  }

 private:
  // Every vertex of the surface at `p` matched by stereo (at working size);
  // returns how many matched.
  size_t Match(const std::vector<Eigen::Vector3d>& p, const StereoViews& views,
               std::vector<StereoTarget>* out, const ParallelRunner& runner) const;

  const Mesh& mesh_;
  SurfaceTrackingOptions o_;
  std::vector<uint32_t> welded_, canonical_;
  std::vector<std::vector<uint32_t>> ring_;
  std::vector<uint32_t> tris_;  // flat index triples
  std::vector<float> previous_;
  bool started_ = false;
};

}  // namespace fvv

#endif  // FVV_ENCODER_SHAPE_SURFACE_TRACKING_H_
