// Renderer I's parts: silhouette expansion, per-vertex visibility from
// displaced cameras, blending weights, and the GL projection (lens distortion
// included) against the calibration code's.
#include <Eigen/Geometry>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>

#include "encoder/capture/calibration.h"
#include "encoder/shape/projective_texturing.h"
#include "gtest/gtest.h"
#include "player/decoder/public_camera.h"
#include "player/render/headless.h"
#include "player/render/projective_renderer.h"

namespace fvv {
namespace {

// A camera at the origin looking down +z (world = camera coordinates).
Camera FrontCamera(uint32_t size) {
  Camera c;
  c.name = "front";
  c.width = c.height = size;
  c.fx = c.fy = size;
  c.cx = c.cy = (size - 1) / 2.0;
  return c;
}

// A camera at `centre` looking at the origin, y down in its image.
Camera LookingAtOrigin(const Eigen::Vector3d& centre, uint32_t size) {
  Camera c = FrontCamera(size);
  const Eigen::Vector3d z = (-centre).normalized();
  const Eigen::Vector3d x = Eigen::Vector3d(0, -1, 0).cross(z).normalized();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d r;
  r.row(0) = x;
  r.row(1) = y;
  r.row(2) = z;
  for (int i = 0; i < 9; ++i) c.rotation[i] = r(i / 3, i % 3);
  const Eigen::Vector3d t = -r * centre;
  for (int i = 0; i < 3; ++i) c.translation[i] = t[i];
  return c;
}

// A square grid of quads in the plane z = `z`, facing -z (the front camera).
void AddGrid(double z, double half, int cells, std::vector<Eigen::Vector3f>* positions,
             std::vector<std::array<uint32_t, 3>>* triangles) {
  const uint32_t base = uint32_t(positions->size());
  for (int j = 0; j <= cells; ++j) {
    for (int i = 0; i <= cells; ++i) {
      positions->emplace_back(float(-half + 2 * half * i / cells),
                              float(-half + 2 * half * j / cells), float(z));
    }
  }
  const auto at = [&](int i, int j) { return base + uint32_t(j * (cells + 1) + i); };
  for (int j = 0; j < cells; ++j) {
    for (int i = 0; i < cells; ++i) {
      triangles->push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      triangles->push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  }
}

// The silhouette grows by the given pixels with the actor's colour; beyond,
// every pixel takes the actor's colour too, at kFarFillAlpha (what fills
// Renderer I where no silhouette covers the model); the studio's never.
TEST(ExpandSilhouette, GrowsByTheGivenPixelsAndFillsTheRestWithTheActorsColour) {
  Image rgb, sil;
  rgb.width = sil.width = 20;
  rgb.height = sil.height = 20;
  rgb.channels = 3;
  sil.channels = 1;
  rgb.pixels.assign(20 * 20 * 3, 0);
  sil.pixels.assign(20 * 20, 0);
  for (int y = 0; y < 20; ++y) {
    for (int x = 0; x < 20; ++x) {
      const size_t i = size_t(y) * 20 + x;
      const bool actor = x >= 8 && x < 12 && y >= 8 && y < 12;
      sil.pixels[i] = actor ? 255 : 0;
      // Actor red, studio green.
      rgb.pixels[i * 3 + (actor ? 0 : 1)] = 200;
    }
  }
  const Image out = ExpandSilhouette(rgb, sil, 3);
  ASSERT_EQ(out.channels, 4u);
  for (int y = 0; y < 20; ++y) {
    for (int x = 0; x < 20; ++x) {
      const size_t i = size_t(y) * 20 + x;
      // Chebyshev distance to the 4x4 actor square.
      const int dx = std::max({8 - x, x - 11, 0}), dy = std::max({8 - y, y - 11, 0});
      const bool inside = std::max(dx, dy) <= 3;
      EXPECT_EQ(out.pixels[i * 4 + 3], inside ? 255 : kFarFillAlpha) << x << "," << y;
      EXPECT_EQ(out.pixels[i * 4 + 0], 200) << "the actor's colour at " << x << "," << y;
      EXPECT_EQ(out.pixels[i * 4 + 1], 0) << "the studio's colour at " << x << "," << y;
    }
  }
  // No silhouette: every pixel kept as it is.
  const Image all = ExpandSilhouette(rgb, Image(), 3);
  for (size_t i = 0; i < 400; ++i) {
    EXPECT_EQ(all.pixels[i * 4 + 3], 255);
    EXPECT_EQ(all.pixels[i * 4 + 1], rgb.pixels[i * 3 + 1]);
  }
  // A silhouette with no pixel: nothing of this camera is the actor.
  sil.pixels.assign(20 * 20, 0);
  const Image none = ExpandSilhouette(rgb, sil, 3);
  for (size_t i = 0; i < 400; ++i) EXPECT_EQ(none.pixels[i * 4 + 3], 0);
}

TEST(VertexVisibility, OccludedVerticesAndThoseAtTheOccludersEdgeAreHidden) {
  // A wall 3 m in front of the camera behind a 0.4 m square 2 m in front.
  std::vector<Eigen::Vector3f> positions;
  std::vector<std::array<uint32_t, 3>> triangles;
  AddGrid(3.0, 1.0, 100, &positions, &triangles);  // 2 cm spacing
  const size_t wall = positions.size();
  AddGrid(2.0, 0.2, 4, &positions, &triangles);
  std::vector<Eigen::Vector3f> normals(positions.size(), Eigen::Vector3f(0, 0, -1));
  const std::vector<Camera> cameras = {FrontCamera(400)};
  ProjectiveOptions o;
  o.shift_m = 0;
  const auto plain = VertexVisibility(triangles, positions, normals, cameras, o);
  o.shift_m = 0.05;
  const auto shifted = VertexVisibility(triangles, positions, normals, cameras, o);
  int hidden = 0, edge_hidden_only_shifted = 0;
  for (size_t v = 0; v < wall; ++v) {
    // The occluder's shadow on the wall: |x|, |y| < 0.2 * 3 / 2 = 0.3.
    const double r = std::max(std::abs(positions[v].x()), std::abs(positions[v].y()));
    if (r < 0.29) {
      EXPECT_EQ(plain[0][v], 0) << "vertex " << v << " behind the occluder";
      ++hidden;
    } else if (r > 0.31) {
      EXPECT_EQ(plain[0][v], 1) << "vertex " << v << " in plain view";
      // 5 cm shifts at 2 m widen the shadow on the wall by 2.5 cm.
      if (r > 0.33) {
        EXPECT_EQ(shifted[0][v], 1) << "vertex " << v << " well clear of the edge";
      }
    }
    // Beside an edge of the shadow (not a corner, which the axis-aligned
    // shifts do not reach).
    const double along = std::min(std::abs(positions[v].x()), std::abs(positions[v].y()));
    if (r > 0.305 && r < 0.32 && along < 0.28) {
      EXPECT_EQ(plain[0][v], 1);
      EXPECT_EQ(shifted[0][v], 0) << "vertex " << v << " at the occluding edge";
      ++edge_hidden_only_shifted;
    }
  }
  EXPECT_GT(hidden, 500);
  EXPECT_GT(edge_hidden_only_shifted, 20);
  for (size_t v = wall; v < positions.size(); ++v) EXPECT_EQ(plain[0][v], 1);
  // Back-facing vertices are never visible.
  std::vector<Eigen::Vector3f> flipped(positions.size(), Eigen::Vector3f(0, 0, 1));
  const auto back = VertexVisibility(triangles, positions, flipped, cameras, o);
  for (uint8_t b : back[0]) EXPECT_EQ(b, 0);
}

TEST(BlendWeights, NormalisedBestCameraDominatesMoreWithHigherDominance) {
  // One vertex at the origin facing +z; cameras at 10, 30 and 60 degrees off
  // the normal, and one that does not see it.
  const std::vector<Eigen::Vector3f> positions = {Eigen::Vector3f(0, 0, 0)};
  const std::vector<Eigen::Vector3f> normals = {Eigen::Vector3f(0, 0, 1)};
  std::vector<Camera> cameras;
  for (double deg : {10.0, 30.0, 60.0, 20.0}) {
    const double a = deg * M_PI / 180;
    cameras.push_back(LookingAtOrigin(3 * Eigen::Vector3d(std::sin(a), 0, std::cos(a)), 64));
  }
  const std::vector<std::vector<uint8_t>> vis = {{1}, {1}, {1}, {0}};
  double last_share = 0;
  for (double alpha : {0.5, 1.0, 2.0, 4.0}) {
    const std::vector<float> w = BlendWeights(positions, normals, cameras, vis, alpha);
    ASSERT_EQ(w.size(), 4u);
    // Normalised, plus the fallback weight on the best-facing camera.
    EXPECT_NEAR(w[0] + w[1] + w[2], 1.0 + kFallbackWeight, 1e-6);
    EXPECT_EQ(w[3], 0.0f) << "a camera that does not see the vertex weighs nothing";
    EXPECT_GT(w[0], w[1]);
    EXPECT_GT(w[1], w[2]);
    EXPECT_GT(w[0], last_share) << "alpha " << alpha;
    last_share = w[0];
  }
  // Seen by no camera: only the best-facing one, at the fallback weight.
  const std::vector<std::vector<uint8_t>> none = {{0}, {0}, {0}, {0}};
  const std::vector<float> w = BlendWeights(positions, normals, cameras, none, 2.0);
  EXPECT_FLOAT_EQ(w[0], kFallbackWeight);
  EXPECT_EQ(w[1] + w[2] + w[3], 0.0f);
}

TEST(ProjectiveRenderer, ProjectsThroughTheLensLikeTheCalibration) {
  // A 128x128 camera with strong lens distortion whose image holds its own
  // pixel coordinates (R = x, G = y): rendering a wall from the same camera's
  // pinhole view, each pixel must show where the distorted projection of its
  // surface point lands, whatever the surface's depth.
  constexpr int kSize = 128;
  Camera cam = FrontCamera(kSize);
  cam.fx = cam.fy = 100;
  cam.distortion = {0.12, -0.03, 0.004, -0.003, 0.01};
  std::vector<Eigen::Vector3f> positions;
  std::vector<std::array<uint32_t, 3>> tris;
  AddGrid(2.5, 3.0, 8, &positions, &tris);
  std::vector<float> flat;
  for (const auto& p : positions) flat.insert(flat.end(), {p.x(), p.y(), p.z()});
  std::vector<uint32_t> indices;
  for (const auto& t : tris) indices.insert(indices.end(), t.begin(), t.end());
  std::vector<uint8_t> image(kSize * kSize * 4);
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) {
      uint8_t* p = &image[(size_t(y) * kSize + x) * 4];
      p[0] = uint8_t(x), p[1] = uint8_t(y), p[2] = 0, p[3] = 255;
    }
  }
  auto ctx = HeadlessContext::Create(kSize, kSize);
  ASSERT_TRUE(ctx.ok()) << ctx.status().ToString();
  const fvv_camera pub = PublicCamera(cam);
  auto r = ProjectiveRenderer::Create((*ctx)->gl(), indices, uint32_t(positions.size()), {pub});
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  const std::vector<float> weights(positions.size(), 1.0f);
  ASSERT_TRUE((*r)->SetFrame(flat, weights, {image.data()}).ok());
  RenderView view;
  CameraViewProjection(pub, 0.05f, 50.0f, &view.view, &view.projection);
  ASSERT_TRUE((*r)->Draw(view, kSize, kSize).ok());
  std::vector<uint8_t> rgb;
  ASSERT_TRUE((*r)->ReadRgb(kSize, kSize, &rgb).ok());
  Camera pinhole = cam;
  pinhole.distortion = {};
  int checked = 0;
  double worst = 0;
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) {
      Eigen::Vector2d d;
      ASSERT_TRUE(ProjectPoint(cam, UnprojectPixel(pinhole, Eigen::Vector2d(x, y), 2.5), &d));
      if (!(d.x() >= 1 && d.y() >= 1 && d.x() <= kSize - 2 && d.y() <= kSize - 2)) continue;
      const uint8_t* p = &rgb[(size_t(y) * kSize + x) * 3];
      worst = std::max({worst, std::abs(p[0] - d.x()), std::abs(p[1] - d.y())});
      ++checked;
    }
  }
  EXPECT_GT(checked, kSize * kSize / 2);
  // Half a level of 8-bit rounding plus float round-off in the shader.
  EXPECT_LT(worst, 0.6) << "the shader's projection is off the calibration's";
  // Distortion matters here: a pinhole projection would be far off.
  Eigen::Vector2d corner;
  ASSERT_TRUE(ProjectPoint(cam, UnprojectPixel(pinhole, Eigen::Vector2d(10, 10), 2.5), &corner));
  EXPECT_GT(std::abs(corner.x() - 10), 3.0);
}

}  // namespace
}  // namespace fvv
