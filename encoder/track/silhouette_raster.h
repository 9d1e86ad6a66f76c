// Silhouette rasterisation for the tracker: sets the pixels whose
// centres lie inside a mesh's front-facing triangles. It runs tens of millions
// of times per tracked frame on triangles a few pixels in size, so the
// per-pixel test runs on four pixels of a row at once (SSE2), computing exactly
// what the scalar definition below computes.
#ifndef FVV_ENCODER_TRACK_SILHOUETTE_RASTER_H_
#define FVV_ENCODER_TRACK_SILHOUETTE_RASTER_H_

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace fvv {

struct RasterBox {
  int x0, y0, x1, y1;  // inclusive; empty when x0 > x1
};

// Whether pixel centre (x, y) lies inside triangle a, b, c (image coordinates,
// y down) whose signed area is `area` < 0 (front facing): the definition the
// span rasteriser reproduces exactly.
inline bool PixelInTriangle(const Eigen::Vector2f& a, const Eigen::Vector2f& b,
                            const Eigen::Vector2f& c, float inv_area, int x, int y) {
  const float w0 = ((c.x() - b.x()) * (y - b.y()) - (c.y() - b.y()) * (x - b.x())) * inv_area;
  const float w1 = ((a.x() - c.x()) * (y - c.y()) - (a.y() - c.y()) * (x - c.x())) * inv_area;
  return w0 >= 0 && w1 >= 0 && w0 + w1 <= 1;
}

// Sets to 1 the pixels of the w x h image `out` inside the front-facing
// triangles `tris` (index triples into `px`; pixel centres at integer
// coordinates, as the calibration's); grows `box` by each drawn triangle's
// clipped bounding box.
void RasteriseSilhouette(const std::vector<uint32_t>& tris, const std::vector<Eigen::Vector2f>& px,
                         int w, int h, uint8_t* out, RasterBox* box);

}  // namespace fvv

#endif  // FVV_ENCODER_TRACK_SILHOUETTE_RASTER_H_
