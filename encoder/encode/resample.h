// Multi-view resampling into the texture atlas: for one
// frame and one camera, every atlas texel's surface point on the posed model is
// projected into that camera's image and sampled there, when the camera sees it:
// in front of the camera's depth map of the posed model (shadow-map style),
// facing the camera, and inside the image silhouette grown or shrunk by a
// margin (SilhouetteMargin). Texels the camera does not see are unused.
//
// For streams without masks it also marks the texels a player may take from
// the camera (container/geometric_visibility.h), loosened so that it covers
// the player's coarser depth maps: facing, inside the image, and in front of
// the depth map's largest value within one player depth texel.
//
// The atlas-space rasterisation is done once per atlas (TexelMap): which
// triangle covers each texel and where, so each view only interpolates the
// posed vertices.
#ifndef FVV_ENCODER_ENCODE_RESAMPLE_H_
#define FVV_ENCODER_ENCODE_RESAMPLE_H_

#include <Eigen/Core>
#include <array>
#include <optional>
#include <vector>

#include "container/body_model.h"
#include "container/cameras.h"
#include "encoder/encode/occluders.h"
#include "encoder/io/image_io.h"

namespace fvv {

// The atlas texels the mesh covers: texel centres inside a triangle in UV
// space, plus texels within `dilation` texels of one (charts grow into their
// gutters, so bilinear texture filtering at chart borders reads real samples).
struct TexelMap {
  uint32_t size = 0;
  std::vector<uint32_t> texel;                // y * size + x
  std::vector<uint32_t> triangle;             // covering triangle, per entry
  std::vector<std::array<float, 3>> weights;  // barycentric weights of its vertices
};
TexelMap MapAtlasTexels(const Mesh& mesh, uint32_t size, double dilation = 1.0);

// Entry `e`'s point and unit normal on the surface of `triangles` with these
// vertex positions and normals (the bind pose's or a posed frame's):
// its triangle's vertices weighted by its barycentric weights.
void TexelSurfacePoint(const TexelMap& map, const std::vector<std::array<uint32_t, 3>>& triangles,
                       const std::vector<Eigen::Vector3f>& positions,
                       const std::vector<Eigen::Vector3f>& normals, size_t e, Eigen::Vector3f* p,
                       Eigen::Vector3f* n);

// The image silhouette's margin by where it comes from. Given or subtracted
// silhouettes are pixel-accurate: grown a little, so that texels near the
// outline are kept where the model and the silhouette disagree slightly. The
// person network's masks are coarse: it cuts them on 256 cells across a
// square about 1.25 times the person, so a cell is about a 200th of the
// person's extent, and the outline pixels mix the actor with what stands
// behind him. Samples come from half a cell inside: the person's extent (the
// longer side of the mask's box) over kPersonExtentPerMarginPixel, at least
// a pixel.
constexpr int kSilhouetteMargin = 2;
constexpr double kPersonExtentPerMarginPixel = 400;
int PersonMaskMargin(const Image& silhouette);
int SilhouetteMargin(const std::optional<int>& setting, bool person_masks, const Image& silhouette);

struct ResampleOptions {
  // Pixels the image silhouette grows by; negative shrinks it. Unset: by the
  // silhouettes' source (SilhouetteMargin).
  std::optional<int> silhouette_margin;
  bool person_masks = false;      // the silhouettes are the person network's masks
  double depth_tolerance = 0.02;  // metres behind the depth map still counted visible
  double min_facing = 0.1;        // cosine of the largest viewing angle to the normal
  // Something else must stand this far (metres) in front of a surface point
  // to hide it (encoder/encode/occluders.h).
  double occluder_clearance = 0.2;
};

// One view: `positions` and `normals` are the mesh's vertices posed (world
// space). `silhouette` may be empty (no silhouette test). Writes `rgb`
// (size * size * 3) and `mask` (size * size, 1 = seen); unseen texels are 0.
// `usable` (size * size, may be null) gets 1 where a player of a stream
// without masks may take the texel from this camera; every seen texel is.
// `occluders` (may be null): what else stands in the camera's view; a texel
// behind it is not seen, and counted in `hidden` (may be null).
void ResampleView(const TexelMap& map, const Mesh& mesh,
                  const std::vector<Eigen::Vector3f>& positions,
                  const std::vector<Eigen::Vector3f>& normals, const Camera& camera,
                  const Image& image, const Image& silhouette, const ResampleOptions& options,
                  uint8_t* rgb, uint8_t* mask, uint8_t* usable = nullptr,
                  const OccluderDepth* occluders = nullptr, uint64_t* hidden = nullptr);

}  // namespace fvv

#endif  // FVV_ENCODER_ENCODE_RESAMPLE_H_
