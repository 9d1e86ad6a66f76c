// The cameras' colour responses read from the actor's surface: on a sphere
// filmed by cameras of known responses (exact geometry), and on the synthetic
// actor tracked with its true poses (sensor noise, shading, a body's
// self-occlusion), the gains found bring every camera to one colour.
#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>

#include "encoder/body/generic_body.h"
#include "encoder/body/kinematics.h"
#include "encoder/capture/calibration.h"
#include "encoder/capture/capture.h"
#include "encoder/capture/colour_gain.h"
#include "encoder/encode/pose_file.h"
#include "encoder/shape/colour_calibration.h"
#include "encoder/track/capture_frames.h"
#include "tools/synth/synth.h"

namespace fvv {
namespace {

constexpr uint32_t kWidth = 320, kHeight = 240;

// A camera at `centre` looking at `target`, y down in its image.
Camera Looking(const Eigen::Vector3d& centre, const Eigen::Vector3d& target, const char* name) {
  Camera c;
  c.name = name;
  c.width = kWidth, c.height = kHeight;
  c.fx = c.fy = 300;
  c.cx = (kWidth - 1) / 2.0, c.cy = (kHeight - 1) / 2.0;
  const Eigen::Vector3d z = (target - centre).normalized();
  const Eigen::Vector3d x = Eigen::Vector3d(0, -1, 0).cross(z).normalized();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d r;
  r.row(0) = x, r.row(1) = y, r.row(2) = z;
  for (int i = 0; i < 9; ++i) c.rotation[i] = r(i / 3, i % 3);
  const Eigen::Vector3d t = -r * centre;
  for (int i = 0; i < 3; ++i) c.translation[i] = t[i];
  return c;
}

// The sphere's own colour at surface point p: smooth, within 50..190.
std::array<double, 3> SurfaceColour(const Eigen::Vector3d& p) {
  std::array<double, 3> c;
  for (int k = 0; k < 3; ++k)
    c[k] = 120 + 70 * std::sin(5 * p.x() + 2 * k) * std::cos(4 * p.y() - k);
  return c;
}

// A sphere of radius `r` at the origin, filmed: colour through the camera's
// response where a pixel's ray meets it (its silhouette there), grey beside.
void Film(const Camera& cam, double r, const std::array<double, 3>& response, Image* image,
          Image* silhouette) {
  image->width = silhouette->width = kWidth;
  image->height = silhouette->height = kHeight;
  image->channels = 3, silhouette->channels = 1;
  image->pixels.assign(size_t(kWidth) * kHeight * 3, 100);
  silhouette->pixels.assign(size_t(kWidth) * kHeight, 0);
  const Eigen::Vector3d o = CameraCentre(cam);
  for (uint32_t y = 0; y < kHeight; ++y) {
    for (uint32_t x = 0; x < kWidth; ++x) {
      const Eigen::Vector3d d = (UnprojectPixel(cam, Eigen::Vector2d(x, y), 1.0) - o).normalized();
      const double b = o.dot(d), disc = b * b - (o.squaredNorm() - r * r);
      if (disc < 0) continue;
      const Eigen::Vector3d hit = o + (-b - std::sqrt(disc)) * d;
      const std::array<double, 3> c = SurfaceColour(hit);
      const size_t i = size_t(y) * kWidth + x;
      for (int k = 0; k < 3; ++k) {
        image->pixels[3 * i + k] = uint8_t(std::clamp(std::lround(c[k] * response[k]), 0L, 255L));
      }
      silhouette->pixels[i] = 255;
    }
  }
}

// A UV sphere: vertices on the surface, outward normals, triangles wound
// counter-clockwise seen from outside.
void Sphere(double r, int rings, int segments, std::vector<Eigen::Vector3f>* positions,
            std::vector<Eigen::Vector3f>* normals,
            std::vector<std::array<uint32_t, 3>>* triangles) {
  for (int i = 0; i <= rings; ++i) {
    const double theta = M_PI * i / rings;
    for (int j = 0; j < segments; ++j) {
      const double phi = 2 * M_PI * j / segments;
      const Eigen::Vector3f n(float(std::sin(theta) * std::cos(phi)), float(std::cos(theta)),
                              float(std::sin(theta) * std::sin(phi)));
      normals->push_back(n);
      positions->push_back(float(r) * n);
    }
  }
  const auto at = [&](int i, int j) { return uint32_t(i * segments + (j % segments)); };
  for (int i = 0; i < rings; ++i) {
    for (int j = 0; j < segments; ++j) {
      triangles->push_back({at(i, j), at(i, j + 1), at(i + 1, j)});
      triangles->push_back({at(i, j + 1), at(i + 1, j + 1), at(i + 1, j)});
    }
  }
}

// gains[c] * responses[c] the same for every camera, within `tolerance`.
void ExpectOneColour(const std::vector<std::array<double, 3>>& gains,
                     const std::vector<std::array<double, 3>>& responses, double tolerance) {
  for (int k = 0; k < 3; ++k) {
    const double common = gains[0][k] * responses[0][k];
    for (size_t c = 1; c < gains.size(); ++c) {
      EXPECT_NEAR(gains[c][k] * responses[c][k] / common, 1.0, tolerance)
          << "camera " << c << " channel " << k;
    }
  }
}

TEST(ColourCalibration, BringsCamerasOfKnownResponsesToOneColour) {
  const double r = 0.5;
  std::vector<Camera> cameras;
  const char* names[] = {"a", "b", "c", "d", "e"};
  for (int c = 0; c < 5; ++c) {
    const double angle = 2 * M_PI * c / 5;
    cameras.push_back(
        Looking({3 * std::sin(angle), -0.3, 3 * std::cos(angle)}, {0, 0, 0}, names[c]));
  }
  // A sixth camera looking away: it shares nothing with the others.
  cameras.push_back(Looking({0, 0, 3}, {0, 0, 6}, "away"));
  const std::vector<std::array<double, 3>> responses = {{1.0, 1.0, 1.0},  {0.85, 0.9, 0.8},
                                                        {1.2, 1.1, 1.25}, {0.95, 1.05, 1.0},
                                                        {1.1, 0.9, 0.95}, {0.7, 0.7, 0.7}};
  std::vector<Eigen::Vector3f> positions, normals;
  std::vector<std::array<uint32_t, 3>> triangles;
  Sphere(r, 80, 160, &positions, &normals, &triangles);
  std::vector<Image> images(cameras.size()), silhouettes(cameras.size());
  for (size_t c = 0; c < cameras.size(); ++c) {
    Film(cameras[c], r, responses[c], &images[c], &silhouettes[c]);
  }
  ColourCalibration calibration(cameras);
  ASSERT_TRUE(calibration.AddFrame(triangles, positions, normals, images, silhouettes).ok());
  StatusOr<ColourCalibrationResult> result = calibration.Solve();
  ASSERT_TRUE(result.ok()) << result.status().ToString();
  for (size_t c = 0; c < 5; ++c) EXPECT_TRUE(result->calibrated[c]) << c;
  EXPECT_FALSE(result->calibrated[5]);
  EXPECT_EQ(result->gains[5], (std::array<double, 3>{1.0, 1.0, 1.0}));
  ExpectOneColour({result->gains.begin(), result->gains.begin() + 5},
                  {responses.begin(), responses.begin() + 5}, 0.01);
  // The rig's common colour: the calibrated gains' geometric mean is 1.
  for (int k = 0; k < 3; ++k) {
    double log_sum = 0;
    for (size_t c = 0; c < 5; ++c) log_sum += std::log(result->gains[c][k]);
    EXPECT_NEAR(log_sum, 0.0, 1e-9);
  }
  EXPECT_GT(result->difference_before, 0.08);
  EXPECT_LT(result->difference_after, 0.01);

  // Equal cameras need no gain.
  std::vector<Image> same(5), same_sil(5);
  for (size_t c = 0; c < 5; ++c) Film(cameras[c], r, {1, 1, 1}, &same[c], &same_sil[c]);
  ColourCalibration equal({cameras.begin(), cameras.begin() + 5});
  ASSERT_TRUE(equal.AddFrame(triangles, positions, normals, same, same_sil).ok());
  StatusOr<ColourCalibrationResult> unit = equal.Solve();
  ASSERT_TRUE(unit.ok());
  for (const auto& g : unit->gains) {
    for (double v : g) EXPECT_NEAR(v, 1.0, 0.005);
  }
}

TEST(ColourCalibration, RefusesWhatItCannotUse) {
  std::vector<Eigen::Vector3f> positions, normals;
  std::vector<std::array<uint32_t, 3>> triangles;
  Sphere(0.5, 10, 20, &positions, &normals, &triangles);
  const std::vector<Camera> cameras = {Looking({0, 0, 3}, {0, 0, 0}, "a"),
                                       Looking({0, 0, -3}, {0, 0, 0}, "b")};
  std::vector<Image> images(2), silhouettes(2);
  for (size_t c = 0; c < 2; ++c) Film(cameras[c], 0.5, {1, 1, 1}, &images[c], &silhouettes[c]);
  ColourCalibration calibration(cameras);
  // One image short.
  Status s = calibration.AddFrame(triangles, positions, normals, {images[0]}, {});
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.message().find("1 images for 2 cameras"), std::string::npos) << s.ToString();
  // A wrong size.
  std::vector<Image> small = images;
  small[1].width = 10;
  s = calibration.AddFrame(triangles, positions, normals, small, silhouettes);
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.message().find("\"b\""), std::string::npos) << s.ToString();
  // Cameras facing each other across the sphere share no point.
  ASSERT_TRUE(calibration.AddFrame(triangles, positions, normals, images, silhouettes).ok());
  StatusOr<ColourCalibrationResult> r = calibration.Solve();
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("no two cameras see enough"), std::string::npos)
      << r.status().ToString();
}

// The synthetic actor, lit, with sensor noise and cameras of different
// responses (fvv synth --colour-mismatch), on its true poses: what a tracked
// take gives, less the fit's error.
TEST(ColourCalibration, FindsTheSyntheticStudiosResponses) {
  const std::string dir = ::testing::TempDir() + "/colour_calibration_" + std::to_string(getpid());
  std::system(("rm -rf '" + dir + "'").c_str());
  SynthOptions o;
  o.output_dir = dir;
  o.cameras = 6;
  o.frames = 3;
  o.held_out = 0;
  o.colour_mismatch = 0.15;
  o.seed = 3;
  ASSERT_TRUE(RunSynth(o).ok());
  StatusOr<Capture> cap = LoadCapture(dir);
  ASSERT_TRUE(cap.ok()) << cap.status().ToString();
  StatusOr<PoseSequence> poses = LoadPoseFile(dir);
  ASSERT_TRUE(poses.ok()) << poses.status().ToString();
  std::ifstream in(dir + "/truth/truth.json");
  const nlohmann::json truth = nlohmann::json::parse(in);
  const auto responses = truth["camera_responses"].get<std::vector<std::array<double, 3>>>();
  ASSERT_EQ(responses.size(), 6u);

  const BodyModel body = MakeGenericBody(poses->shape);
  std::vector<Camera> cameras;
  for (const CaptureCamera& c : cap->cameras) cameras.push_back(c.calibration);
  ColourCalibration calibration(cameras);
  CaptureReader reader(*cap);
  for (uint32_t f = 0; f < 3; ++f) {
    std::vector<Image> images, silhouettes;
    for (uint32_t c = 0; c < 6; ++c) {
      StatusOr<Image> image = reader.ReadFrame(c, f);
      ASSERT_TRUE(image.ok()) << image.status().ToString();
      images.push_back(*image);
    }
    std::vector<Eigen::Vector3f> normals;
    const std::vector<Eigen::Vector3f> positions =
        SkinPositions(body.mesh, SkinningMatrices(body.skeleton, poses->poses[f]), &normals);
    // No silhouettes: the depth maps alone, the inner margin unused.
    ASSERT_TRUE(calibration.AddFrame(body.mesh.triangles, positions, normals, images, {}).ok());
  }
  StatusOr<ColourCalibrationResult> r = calibration.Solve();
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  ExpectOneColour(r->gains, responses, 0.02);
  EXPECT_LT(r->difference_after, r->difference_before / 2);
  std::system(("rm -rf '" + dir + "'").c_str());
}

TEST(ColourGain, ScalesRoundsClipsAndInverts) {
  Image im;
  im.width = 2, im.height = 1, im.channels = 3;
  im.pixels = {100, 100, 100, 250, 3, 0};
  ApplyColourGain({1.5, 0.5, 1.0}, &im);
  EXPECT_EQ(im.pixels, (std::vector<uint8_t>{150, 50, 100, 255, 2, 0}));
  Image grey;
  grey.width = 3, grey.height = 1, grey.channels = 1;
  grey.pixels = {10, 20, 30};
  ApplyColourGain({2, 2, 2}, &grey);
  EXPECT_EQ(grey.pixels, (std::vector<uint8_t>{10, 20, 30}));
  EXPECT_TRUE(IsUnitGain({1, 1, 1}));
  EXPECT_FALSE(IsUnitGain({1, 1, 1.01}));
  EXPECT_EQ(InverseGain({2, 0.5, 4}), (std::array<double, 3>{0.5, 2, 0.25}));
}

}  // namespace
}  // namespace fvv
