// The convex hull of an actor's silhouette, in the camera's undistorted
// normalised coordinates: what a line through a point outside it can touch.
// Lines through another camera's centre (epipolar lines) that touch two
// cameras' silhouettes of one instant meet the same point of the actor's
// surface (a frontier point), whatever his shape, so the hull is all the
// camera calibration from silhouettes needs of a frame (tangent_calibration.h).
#ifndef FVV_ENCODER_TRACK_OUTLINE_HULL_H_
#define FVV_ENCODER_TRACK_OUTLINE_HULL_H_

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "container/cameras.h"
#include "encoder/io/image_io.h"

namespace fvv {

struct OutlineHull {
  // Undistorted normalised coordinates, each turn to the next a positive one
  // (a positive cross product); empty for an empty mask.
  std::vector<Eigen::Vector2d> points;
  // Per point: its pixel lies within `border_px` of the image's edge, where the
  // silhouette may go on beyond what the camera saw.
  std::vector<uint8_t> at_border;
};

// The hull of the non-zero pixels of `mask` (the camera's image size), each
// pixel taken as the square it covers.
OutlineHull MakeOutlineHull(const Camera& camera, const Image& mask, int border_px = 2);

// Whether `p` lies inside the hull (or on it).
bool InsideOutlineHull(const OutlineHull& hull, const Eigen::Vector2d& p);

}  // namespace fvv

#endif  // FVV_ENCODER_TRACK_OUTLINE_HULL_H_
