// Model-based stereo: where along a camera's ray a surface point lies, by
// matching a small patch laid on the model's local surface between that
// camera (the key: the one facing the surface best) and its neighbours, by
// normalised cross-correlation of luma. Shape refinement (one frame, full
// resolution) and surface tracking (every frame, at working size) share it.
#ifndef FVV_ENCODER_SHAPE_PATCH_STEREO_H_
#define FVV_ENCODER_SHAPE_PATCH_STEREO_H_

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "container/cameras.h"
#include "encoder/io/image_io.h"

namespace fvv {

// Luma (BT.601) as floats, and bilinear samples of it (NaN outside).
struct GreyImage {
  int width = 0, height = 0;
  std::vector<float> pixels;
  float At(const Eigen::Vector2d& q) const;
};

// `rgb` (3 or 4 channels) reduced by `factor` each way (box means over whole
// blocks, as ReducedCamera scales a calibration).
GreyImage Grey(const Image& rgb, int factor = 1);

// Normalised cross-correlation of two equally long sample vectors; NaN when
// either is flat or has a sample outside its image.
double Ncc(const std::vector<float>& a, const std::vector<float>& b);

// The surface around a vertex as a height over its tangent plane,
// h = a x^2 + b x y + c y^2 along the normal, in the axes u, w (unit, normal
// x u = w). Patches follow it, not the tangent plane: on a limb a flat patch
// a few centimetres wide stands off the surface at its edges, which biases
// matches inwards.
struct LocalSurface {
  Eigen::Vector3d u{1, 0, 0}, w{0, 1, 0};
  double a = 0, b = 0, c = 0;
};

// Fitted to the neighbours `ring` of a vertex at `p` by least squares.
LocalSurface FitSurface(const Eigen::Vector3d& p, const Eigen::Vector3d& normal,
                        const std::vector<uint32_t>& ring,
                        const std::vector<Eigen::Vector3f>& positions);

struct PatchStereoOptions {
  int patch_radius = 2;        // the patch is (2r + 1)^2 samples
  double min_ncc = 0.8;        // weaker matches are not used
  double min_patch_std = 3.0;  // a key patch flatter than this (8-bit levels) has no stereo
  double key_facing = 0.3;     // a key camera looks at the surface, not along it
  double max_angle = 0.9;      // radians between key and neighbour, seen from the point
  // Neighbours within max_angle a match needs (it uses two at most): with two,
  // a false peak of one pair is outvoted by the other.
  int min_neighbours = 2;
};

// The cameras and their luma, as the matcher sees them (the same size each).
struct StereoViews {
  std::vector<Camera> cameras;
  std::vector<Eigen::Vector3d> centres;
  std::vector<GreyImage> grey;
};

struct StereoTarget {
  bool valid = false;
  Eigen::Vector3d point{0, 0, 0};  // where the patch matches, on the key camera's ray
  double score = 0;                // the neighbours' mean correlation there
};

// The point `p` (unit `normal`, local `surface`) searched along the ray of
// the camera facing it best, `range` metres either way, against up to two
// neighbours within options.max_angle (at least options.min_neighbours).
// `visible[c]`: camera c sees `p`.
StereoTarget MatchAlongKeyRay(const StereoViews& views, const std::vector<uint8_t>& visible,
                              const Eigen::Vector3d& p, const Eigen::Vector3d& normal,
                              const LocalSurface& surface, double range,
                              const PatchStereoOptions& options);

}  // namespace fvv

#endif  // FVV_ENCODER_SHAPE_PATCH_STEREO_H_
