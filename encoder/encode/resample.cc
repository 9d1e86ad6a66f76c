#include "encoder/encode/resample.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "container/geometric_visibility.h"
#include "encoder/capture/calibration.h"
#include "encoder/encode/mask_dilation.h"
#include "encoder/io/mask_box.h"
#include "encoder/shape/depth_map.h"

namespace fvv {
namespace {

using Eigen::Vector2f;
using Eigen::Vector3f;

// Closest point of triangle abc to q as barycentric weights, and its distance.
float ClosestOnTriangle(const Vector2f& q, const Vector2f& a, const Vector2f& b, const Vector2f& c,
                        std::array<float, 3>* w) {
  const Vector2f* p[3] = {&a, &b, &c};
  float best = std::numeric_limits<float>::max();
  for (int e = 0; e < 3; ++e) {
    const Vector2f& s = *p[e];
    const Vector2f d = *p[(e + 1) % 3] - s;
    const float len2 = d.squaredNorm();
    const float t = len2 > 0 ? std::clamp((q - s).dot(d) / len2, 0.0f, 1.0f) : 0.0f;
    const float dist = (s + t * d - q).norm();
    if (dist < best) {
      best = dist;
      (*w)[e] = 1 - t;
      (*w)[(e + 1) % 3] = t;
      (*w)[(e + 2) % 3] = 0;
    }
  }
  return best;
}

// The largest depth within `r` pixels of each pixel (square neighbourhood,
// separable max; +infinity, no surface, wins).
std::vector<float> MaxFilter(const DepthMap& depth, int r) {
  const int w = depth.width, h = depth.height;
  std::vector<float> rows(depth.depth.size()), out(depth.depth.size());
  for (int y = 0; y < h; ++y) {
    const float* in = &depth.depth[size_t(y) * w];
    for (int x = 0; x < w; ++x) {
      float v = in[x];
      for (int k = std::max(0, x - r); k <= std::min(w - 1, x + r); ++k) v = std::max(v, in[k]);
      rows[size_t(y) * w + x] = v;
    }
  }
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      float v = rows[size_t(y) * w + x];
      for (int k = std::max(0, y - r); k <= std::min(h - 1, y + r); ++k) {
        v = std::max(v, rows[size_t(k) * w + x]);
      }
      out[size_t(y) * w + x] = v;
    }
  }
  return out;
}

}  // namespace

int PersonMaskMargin(const Image& silhouette) {
  const MaskBox b =
      SetPixelBox(silhouette.pixels.data(), int(silhouette.width), int(silhouette.height));
  const int extent = b.empty() ? 0 : std::max(b.x1 - b.x0, b.y1 - b.y0) + 1;
  return -std::max(1, int(std::lround(extent / kPersonExtentPerMarginPixel)));
}

int SilhouetteMargin(const std::optional<int>& setting, bool person_masks,
                     const Image& silhouette) {
  if (setting) return *setting;
  return person_masks ? PersonMaskMargin(silhouette) : kSilhouetteMargin;
}

TexelMap MapAtlasTexels(const Mesh& mesh, uint32_t size, double dilation) {
  TexelMap map;
  map.size = size;
  const int n = int(size);
  std::vector<float> distance(size_t(n) * n, std::numeric_limits<float>::max());
  std::vector<int32_t> owner(size_t(n) * n, -1);
  std::vector<std::array<float, 3>> weights(size_t(n) * n);
  const float reach = float(dilation);
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    Vector2f p[3];
    for (int k = 0; k < 3; ++k) p[k] = {mesh.uvs[tri[k]][0] * n, mesh.uvs[tri[k]][1] * n};
    const float twice =
        (p[1] - p[0]).x() * (p[2] - p[0]).y() - (p[1] - p[0]).y() * (p[2] - p[0]).x();
    if (!(std::abs(twice) > 1e-12f)) continue;  // degenerate in the atlas: nothing to sample
    const int x0 = std::max(0, int(std::floor(std::min({p[0].x(), p[1].x(), p[2].x()}) - reach)));
    const int x1 =
        std::min(n - 1, int(std::ceil(std::max({p[0].x(), p[1].x(), p[2].x()}) + reach)));
    const int y0 = std::max(0, int(std::floor(std::min({p[0].y(), p[1].y(), p[2].y()}) - reach)));
    const int y1 =
        std::min(n - 1, int(std::ceil(std::max({p[0].y(), p[1].y(), p[2].y()}) + reach)));
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const Vector2f q(x + 0.5f, y + 0.5f);
        std::array<float, 3> w;
        for (int k = 0; k < 3; ++k) {
          const Vector2f& a = p[(k + 1) % 3];
          const Vector2f& c = p[(k + 2) % 3];
          w[k] = ((c - a).x() * (q - a).y() - (c - a).y() * (q - a).x()) / twice;
        }
        float d = 0;
        if (w[0] < 0 || w[1] < 0 || w[2] < 0) {
          d = ClosestOnTriangle(q, p[0], p[1], p[2], &w);
          if (d > reach) continue;
        }
        const size_t i = size_t(y) * n + x;
        if (d < distance[i]) distance[i] = d, owner[i] = int32_t(t), weights[i] = w;
      }
    }
  }
  for (size_t i = 0; i < owner.size(); ++i) {
    if (owner[i] < 0) continue;
    map.texel.push_back(uint32_t(i));
    map.triangle.push_back(uint32_t(owner[i]));
    map.weights.push_back(weights[i]);
  }
  return map;
}

void TexelSurfacePoint(const TexelMap& map, const std::vector<std::array<uint32_t, 3>>& triangles,
                       const std::vector<Vector3f>& positions, const std::vector<Vector3f>& normals,
                       size_t e, Vector3f* p, Vector3f* n) {
  const auto& tri = triangles[map.triangle[e]];
  const auto& bw = map.weights[e];
  *p = bw[0] * positions[tri[0]] + bw[1] * positions[tri[1]] + bw[2] * positions[tri[2]];
  *n = (bw[0] * normals[tri[0]] + bw[1] * normals[tri[1]] + bw[2] * normals[tri[2]]).normalized();
}

void ResampleView(const TexelMap& map, const Mesh& mesh, const std::vector<Vector3f>& positions,
                  const std::vector<Vector3f>& normals, const Camera& camera, const Image& image,
                  const Image& silhouette, const ResampleOptions& o, uint8_t* rgb, uint8_t* mask,
                  uint8_t* usable, const OccluderDepth* occluders, uint64_t* hidden) {
  namespace gv = geometric_visibility;
  const size_t texels = size_t(map.size) * map.size;
  std::fill(rgb, rgb + texels * 3, 0);
  std::fill(mask, mask + texels, 0);
  if (usable) std::fill(usable, usable + texels, 0);
  const int w = int(image.width), h = int(image.height);

  // The camera's depth map of the posed model.
  const DepthMap depth = RenderDepthMap(mesh.triangles, positions, camera);
  std::vector<uint8_t> inside;
  if (!silhouette.pixels.empty()) {
    inside = DilateMask(silhouette.pixels.data(), int(silhouette.width), int(silhouette.height),
                        SilhouetteMargin(o.silhouette_margin, o.person_masks, silhouette));
  }

  const Vector3f centre = CameraCentre(camera).cast<float>();
  // Depth of a surface point's neighbours at the nearest pixel centre differs
  // from its own by up to half a pixel's footprint times the slope; allow that.
  const double pixel_angle = 1.0 / std::max(camera.fx, camera.fy);
  // The player's depth maps: their texels' size, and the deepest surface one
  // of them may hold around each pixel.
  int map_w = 0, map_h = 0;
  gv::DepthMapSize(camera.width, camera.height, &map_w, &map_h);
  const double pixels_per_texel = double(std::max(w, 1)) / map_w;
  const double player_texel_angle = pixel_angle * pixels_per_texel;
  std::vector<float> deepest;
  if (usable) deepest = MaxFilter(depth, int(std::ceil(pixels_per_texel)));
  const uint8_t* src = image.pixels.data();
  for (size_t e = 0; e < map.texel.size(); ++e) {
    Vector3f p, nrm;
    TexelSurfacePoint(map, mesh.triangles, positions, normals, e, &p, &nrm);
    const Vector3f view = centre - p;
    const float facing = nrm.dot(view) / view.norm();
    // Normals interpolated on the GPU differ a little from these.
    if (!(facing >= std::min(o.min_facing, gv::kMinFacing - 0.02))) continue;
    Eigen::Vector2d q;
    double z = 0;
    if (!ProjectPoint(camera, p.cast<double>(), &q, &z)) continue;
    if (!(q.x() >= 0 && q.y() >= 0 && q.x() <= w - 1 && q.y() <= h - 1)) continue;
    const int ix = int(std::lround(q.x())), iy = int(std::lround(q.y()));
    const size_t pixel = size_t(iy) * w + ix;
    if (usable && z <= deepest[pixel] + gv::DepthAllowance(z, facing, player_texel_angle) + 0.01) {
      usable[map.texel[e]] = 1;
    }
    if (!(facing >= o.min_facing)) continue;
    const double slope = std::sqrt(std::max(0.0, 1.0 - double(facing) * facing)) / facing;
    if (z > depth.depth[pixel] + o.depth_tolerance + 0.75 * z * pixel_angle * slope) continue;
    if (!inside.empty() && !inside[pixel]) continue;
    if (occluders && occluders->Hides(ix, iy, z, o.occluder_clearance)) {
      if (hidden) ++*hidden;
      continue;
    }
    // Bilinear sample of the camera image.
    const int x0 = std::min(int(q.x()), w - 2 < 0 ? 0 : w - 2);
    const int y0 = std::min(int(q.y()), h - 2 < 0 ? 0 : h - 2);
    const int x1 = std::min(x0 + 1, w - 1), y1 = std::min(y0 + 1, h - 1);
    const double fx = q.x() - x0, fy = q.y() - y0;
    const size_t out = map.texel[e];
    for (int k = 0; k < 3; ++k) {
      const double top =
          (1 - fx) * src[(size_t(y0) * w + x0) * 3 + k] + fx * src[(size_t(y0) * w + x1) * 3 + k];
      const double bottom =
          (1 - fx) * src[(size_t(y1) * w + x0) * 3 + k] + fx * src[(size_t(y1) * w + x1) * 3 + k];
      rgb[out * 3 + k] = uint8_t(std::lround(std::clamp((1 - fy) * top + fy * bottom, 0.0, 255.0)));
    }
    mask[out] = 1;
    if (usable) usable[out] = 1;
  }
}

}  // namespace fvv
