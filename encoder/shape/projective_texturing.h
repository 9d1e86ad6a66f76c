// What Renderer I needs of one captured frame: the model
// posed, per vertex and camera a 0/1 visibility and a blending weight, and per
// camera its image with the actor's silhouette expanded by a few pixels.
//
// Visibility is precomputed on the CPU from depth maps of the posed model, as
// seen from the camera and from several slightly displaced copies of it: a
// vertex counts as visible only when every copy sees it, so vertices near an
// occluding contour (where a small model or calibration error would project
// the occluder's colours onto them) are left to other cameras.
//
// Weights follow the angle theta_i between the vertex normal and the direction
// to camera i: w_i = 1 / (1 + max_j(1 / theta_j) - 1 / theta_i)^alpha over the
// cameras that see the vertex, normalised to sum 1. The best-facing camera gets
// 1 before normalisation; alpha sets how much it dominates the others. A vertex
// no camera sees takes its colour from the best-facing camera regardless of
// occlusion, at a weight small enough never to matter where any real weight is
// (kFallbackWeight).
#ifndef FVV_ENCODER_SHAPE_PROJECTIVE_TEXTURING_H_
#define FVV_ENCODER_SHAPE_PROJECTIVE_TEXTURING_H_

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "codec/base/parallel.h"
#include "codec/base/status.h"
#include "container/body_model.h"
#include "container/cameras.h"
#include "encoder/io/image_io.h"

namespace fvv {

struct ProjectiveOptions {
  double dominance = 2.0;          // alpha: higher lets the best-facing camera dominate
  double shift_m = 0.01;           // displacement of the extra camera positions
  double depth_tolerance = 0.015;  // metres behind a depth map still counted visible
  double min_facing = 0.05;        // cosine of the largest angle to the normal a camera sees at
  int expand_px = 3;               // silhouettes grow by this many pixels
};

// Weight of the fallback camera of a vertex: far below any real weight (those
// are >= 1 / cameras after normalisation), far above float round-off.
constexpr float kFallbackWeight = 1e-4f;

// Per camera, per vertex: 1 when the camera sees the vertex. `normals` unit.
std::vector<std::vector<uint8_t>> VertexVisibility(
    const std::vector<std::array<uint32_t, 3>>& triangles,
    const std::vector<Eigen::Vector3f>& positions, const std::vector<Eigen::Vector3f>& normals,
    const std::vector<Camera>& cameras, const ProjectiveOptions& options,
    const ParallelRunner& runner = SerialRunner);

// Blending weights, camera-major ([camera][vertex]), from the visibility.
std::vector<float> BlendWeights(const std::vector<Eigen::Vector3f>& positions,
                                const std::vector<Eigen::Vector3f>& normals,
                                const std::vector<Camera>& cameras,
                                const std::vector<std::vector<uint8_t>>& visibility,
                                double dominance);

// RGBA, straight (not premultiplied): alpha 255 inside the silhouette grown by
// `pixels`, kFarFillAlpha beyond. Every pixel outside the silhouette takes the
// colour of the actor pixels nearest it (ring by ring), so a model larger than
// the silhouette picks up the actor, never the studio: within `pixels` as much
// as the silhouette, beyond only where no camera has better (Renderer I weighs
// those samples down, so they fill what would be grey). An empty silhouette
// keeps every pixel (alpha 255); a silhouette with no pixel, none (alpha 0).
constexpr uint8_t kFarFillAlpha = 1;
Image ExpandSilhouette(const Image& rgb, const Image& silhouette, int pixels);

// One frame as Renderer I takes it.
struct ProjectiveFrame {
  std::vector<float> positions;                  // posed vertices, xyz
  std::vector<float> weights;                    // [camera][vertex]
  std::vector<Image> images;                     // per camera RGBA, straight (ExpandSilhouette)
  std::vector<std::vector<uint8_t>> visibility;  // [camera][vertex]
  Eigen::Vector3d root{0, 0, 0};                 // the root joint, where views look
};

// Any mesh in world space (e.g. a visual hull's surface): its visibility and
// weights in the cameras, and their images with expanded silhouettes.
StatusOr<ProjectiveFrame> MakeProjectiveFrameForMesh(
    const std::vector<std::array<uint32_t, 3>>& triangles,
    const std::vector<Eigen::Vector3f>& positions, const std::vector<Eigen::Vector3f>& normals,
    const std::vector<Camera>& cameras, const std::vector<Image>& images,
    const std::vector<Image>& silhouettes, const ProjectiveOptions& options,
    const ParallelRunner& runner = SerialRunner);

// The model posed by `dofs` (generic-body DOF order), its visibility and
// weights in the cameras, and their images with expanded silhouettes (an
// empty silhouette list: none).
StatusOr<ProjectiveFrame> MakeProjectiveFrame(
    const BodyModel& model, const std::vector<double>& dofs, const std::vector<Camera>& cameras,
    const std::vector<Image>& images, const std::vector<Image>& silhouettes,
    const ProjectiveOptions& options, const ParallelRunner& runner = SerialRunner);

}  // namespace fvv

#endif  // FVV_ENCODER_SHAPE_PROJECTIVE_TEXTURING_H_
