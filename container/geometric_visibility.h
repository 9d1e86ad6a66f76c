// Which cameras a player may take a surface point's colour from when a stream
// carries no shape masks (tool bit 7 clear; SPEC.md 7, informative): those
// facing the point whose depth map of the posed model, rendered at a reduced
// resolution, does not hide it. The player (Renderer II) applies the rule on
// the GPU; the encoder applies a looser form of it, so that every texel a
// player may use holds a colour worth showing (docs/encoder.md, "Streams
// without masks").
#ifndef FVV_CONTAINER_GEOMETRIC_VISIBILITY_H_
#define FVV_CONTAINER_GEOMETRIC_VISIBILITY_H_

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace fvv {
namespace geometric_visibility {

// The depth maps' longer side in texels, whatever the camera's resolution:
// small enough that one per camera costs the player little per frame.
constexpr int kDepthMapLongSide = 640;
// A point is seen when its camera z is at most the depth map's plus this many
// metres, plus kSlopeTexels depth-map texels' footprint times the surface's
// slope away from the camera (a tilted surface's depth changes across a texel).
constexpr double kDepthTolerance = 0.02;
constexpr double kSlopeTexels = 1.5;
// fvv's players draw the depth maps from the body simplified to at most this
// share of its triangles, each merge kept within kSimplifyError of the model's
// extent (root mean square distance to the merged triangles' planes: a few
// millimetres on a body, well inside kDepthTolerance); a software
// rasteriser's depth passes cost what their triangles do
// (player/playback/depth_map_triangles.h).
constexpr double kSimplifyShare = 0.25;
constexpr double kSimplifyError = 0.002;
// Facing (cosine between the normal and the direction to the camera): no
// weight at or below kMinFacing, full weight from kFullFacing.
constexpr double kMinFacing = 0.0;
constexpr double kFullFacing = 0.1;

// The reference player's blend (Renderer II's defaults; informative): camera
// c's weight at a surface point is its visibility times
// (kAngleEpsilon / (angle + kAngleEpsilon))^kViewExponent, the angle between
// the directions from the point to the eye and to c, times
// max(facing, 1e-3)^kFacingExponent. The encoder codes a stream without masks
// for this blend (docs/encoder.md, "Streams without masks").
constexpr double kAngleEpsilon = 0.02;
constexpr double kViewExponent = 4.0;
constexpr double kFacingExponent = 8.0;

// The facing ramp of a camera's visibility: 0 at or below kMinFacing, 1 from
// kFullFacing, smoothstep between (GLSL's smoothstep).
inline double FacingRamp(double facing) {
  const double x = std::clamp((facing - kMinFacing) / (kFullFacing - kMinFacing), 0.0, 1.0);
  return x * x * (3 - 2 * x);
}

// The depth map's size for a camera image of width x height.
inline void DepthMapSize(uint32_t width, uint32_t height, int* map_width, int* map_height) {
  const double scale = double(kDepthMapLongSide) / double(std::max<uint32_t>(width, height));
  *map_width = std::max(1, int(std::lround(width * std::min(1.0, scale))));
  *map_height = std::max(1, int(std::lround(height * std::min(1.0, scale))));
}

// The tolerance in metres at camera z `z`, facing `facing`, for depth-map
// texels that each span `texel_angle` radians.
inline double DepthAllowance(double z, double facing, double texel_angle) {
  const double f = std::clamp(facing, 0.05, 1.0);
  const double slope = std::sqrt(std::max(0.0, 1.0 - f * f)) / f;
  return kDepthTolerance + kSlopeTexels * z * texel_angle * slope;
}

}  // namespace geometric_visibility

// A depth map: `triangle_count` triangles (3 vertex indices each) whose
// vertices project to pixel[2 v], pixel[2 v + 1] (pixel centres at integers)
// with 1 / z inv_z[v] (0 or less: at or behind the camera; such triangles are
// skipped, they cannot hide what a camera sees of an actor in front of it),
// rasterised into width x height row-major texels: the nearest camera z at
// each texel centre, interpolated perspective-correctly, +infinity where no
// triangle covers it. The encoder's depth maps and the exporter's share it.
std::vector<float> RasterizeDepth(const uint32_t* triangles, size_t triangle_count,
                                  const double* pixel, const float* inv_z, int width, int height);

}  // namespace fvv

#endif  // FVV_CONTAINER_GEOMETRIC_VISIBILITY_H_
