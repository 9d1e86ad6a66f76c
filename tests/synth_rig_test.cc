// fvv synth --rig: a capture's cameras film the synthetic actor where that
// rig's take put the real one, with the same views (positions, orientations,
// focal lengths, image sizes), so a bench can run a real rig's layout with
// exact calibrations; --calibration-error then films it with cameras turned
// from what capture.json records, as a real calibration is off.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "encoder/body/body_shape_json.h"
#include "encoder/body/kinematics.h"
#include "encoder/capture/calibration.h"
#include "encoder/capture/capture.h"
#include "encoder/encode/pose_file.h"
#include "encoder/io/image_io.h"
#include "tools/synth/rig.h"
#include "tools/synth/synth.h"

namespace fvv {
namespace {

// Four cameras of two image sizes around `target` (on the floor), looking at
// its middle height: a rig whose actor does not stand at the origin.
std::string WriteRig(const std::string& dir, const Eigen::Vector3d& target) {
  Capture c;
  c.directory = dir;
  c.frame_rate = 25;
  c.frame_count = 1;
  for (int i = 0; i < 4; ++i) {
    const double a = 2 * M_PI * i / 4 + 0.3;
    const uint32_t w = i % 2 ? 96 : 90, h = i % 2 ? 160 : 150;
    CaptureCamera cc;
    cc.calibration =
        LookAtCamera("lab" + std::to_string(i), w, h, 1.1 * h,
                     target + Eigen::Vector3d(3.2 * std::sin(a), 1.5 + 0.2 * i, 3.2 * std::cos(a)),
                     target + Eigen::Vector3d(0, 0.9, 0), Eigen::Vector3d(0, 1, 0));
    cc.calibration.distortion = {0.05, -0.01, 0, 0, 0};
    cc.frames.path = cc.calibration.name + "/%06d.png";
    c.cameras.push_back(cc);
  }
  EXPECT_TRUE(MakeDirectories(dir).ok());
  EXPECT_TRUE(SaveCapture(c).ok());
  return dir + "/capture.json";
}

// A short take of `rig`'s cameras into dir/take.
SynthOptions RigTake(const std::string& dir, const std::string& rig, uint32_t frames) {
  SynthOptions o;
  o.output_dir = dir + "/take";
  o.rig = rig;
  o.held_out = 0;
  o.frames = frames;
  o.texture_size = 128;
  return o;
}

std::string TempDir(const std::string& name) {
  return ::testing::TempDir() + "/synth_rig_" + name + "_" + std::to_string(getpid());
}

// The actor's share of the image in the middle third of it, each way.
double CentredShare(const Image& silhouette) {
  int64_t all = 0, middle = 0;
  for (uint32_t y = 0; y < silhouette.height; ++y) {
    for (uint32_t x = 0; x < silhouette.width; ++x) {
      if (!silhouette.pixels[(size_t(y) * silhouette.width + x) * silhouette.channels]) continue;
      ++all;
      middle += 3 * x >= silhouette.width && 3 * x < 2 * silhouette.width;
    }
  }
  return all ? double(middle) / double(all) : 0;
}

TEST(SynthRig, NearestPointToAxesIsWhereTheCamerasLook) {
  const Eigen::Vector3d target(1.5, 0, -0.8);
  const std::string dir = TempDir("axes");
  StatusOr<Capture> c = LoadCapture(WriteRig(dir, target));
  ASSERT_TRUE(c.ok()) << c.status().ToString();
  std::vector<Camera> cams;
  for (const CaptureCamera& cc : c->cameras) cams.push_back(cc.calibration);
  // They look at the target's middle height (0.9 m), from several heights:
  // the nearest point lies over the target.
  const Eigen::Vector3d p = NearestPointToAxes(cams);
  EXPECT_NEAR(p.x(), target.x(), 0.05);
  EXPECT_NEAR(p.z(), target.z(), 0.05);
  EXPECT_EQ(p.y(), 0);
}

TEST(SynthRig, TheRigsCamerasFilmTheActorInTheMiddleOfTheirViews) {
  const Eigen::Vector3d target(1.5, 0, -0.8);
  const std::string dir = TempDir("film");
  const std::string rig = WriteRig(dir + "/lab", target);
  const SynthOptions o = RigTake(dir, rig, 2);
  StatusOr<SynthSummary> s = RunSynth(o);
  ASSERT_TRUE(s.ok()) << s.status().ToString();
  StatusOr<Capture> lab = LoadCapture(rig);
  ASSERT_TRUE(lab.ok());
  ASSERT_EQ(s->capture.cameras.size(), 4u);
  for (size_t i = 0; i < 4; ++i) {
    const Camera& a = lab->cameras[i].calibration;
    const Camera& b = s->capture.cameras[i].calibration;
    EXPECT_EQ(b.name, a.name);
    EXPECT_EQ(b.width, a.width);
    EXPECT_EQ(b.height, a.height);
    EXPECT_EQ(b.fx, a.fx);
    EXPECT_EQ(b.rotation, a.rotation);
    EXPECT_EQ(b.distortion, (std::array<double, 5>{}));
    // Moved on the floor by the point the axes meet.
    const Eigen::Vector3d moved = CameraCentre(b) - CameraCentre(a);
    EXPECT_NEAR(moved.x(), -target.x(), 0.05);
    EXPECT_NEAR(moved.y(), 0, 1e-9);
    EXPECT_NEAR(moved.z(), -target.z(), 0.05);
    // The built-in walk stays near the studio's centre: every camera sees
    // the actor in the middle third of its image (unmoved, he would stand
    // 1.7 m off their axes, at the edge of the views or beyond).
    StatusOr<Image> sil = ReadImage(o.output_dir + "/truth/silhouettes/" + b.name + "/000000.png");
    ASSERT_TRUE(sil.ok()) << sil.status().ToString();
    EXPECT_EQ(sil->width, a.width);
    EXPECT_EQ(sil->height, a.height);
    EXPECT_GT(CentredShare(*sil), 0.95) << b.name;
  }
}

TEST(SynthRig, PosesPutTheActorWhereTheTakePutHimInEveryCamera) {
  const Eigen::Vector3d target(1.5, 0, -0.8);
  const std::string dir = TempDir("poses");
  const std::string rig = WriteRig(dir + "/lab", target);
  // A take's poses in the lab's world: standing at the target, turning.
  BodyShape shape;
  shape.stature = 0.9;
  const Skeleton skeleton = MakeGenericSkeleton(shape);
  const int x = DofIndex(skeleton, kRoot, 3), z = DofIndex(skeleton, kRoot, 5);
  const int yaw = DofIndex(skeleton, kRoot, 1);
  ASSERT_GE(x, 0);
  nlohmann::json frames = nlohmann::json::array();
  std::vector<std::vector<double>> poses;
  for (int f = 0; f < 3; ++f) {
    std::vector<double> dofs(GenericDofNames().size(), 0.0);
    dofs[x] = target.x() + 0.05 * f, dofs[z] = target.z() - 0.03 * f, dofs[yaw] = 0.4 * f;
    frames.push_back({{"frame", 10 + f}, {"dofs", dofs}});
    poses.push_back(dofs);
  }
  const nlohmann::json file = {
      {"dof_names", GenericDofNames()}, {"body_shape", BodyShapeToJson(shape)}, {"frames", frames}};
  const std::string poses_path = dir + "/poses.json";
  std::ofstream(poses_path) << file.dump();

  SynthOptions o = RigTake(dir, rig, 3);
  o.rig_poses = poses_path;
  StatusOr<SynthSummary> s = RunSynth(o);
  ASSERT_TRUE(s.ok()) << s.status().ToString();
  StatusOr<Capture> lab = LoadCapture(rig);
  ASSERT_TRUE(lab.ok());
  // The truth's poses are the take's, moved with the rig, in its proportions.
  StatusOr<PoseSequence> truth = LoadPoseFile(o.output_dir);
  ASSERT_TRUE(truth.ok()) << truth.status().ToString();
  EXPECT_EQ(truth->shape.stature, 0.9);
  ASSERT_EQ(truth->poses.size(), 3u);
  // Every joint projects where the take's joint did in the lab's camera
  // (pinhole: the rig's images leave the lens distortion out).
  for (int f = 0; f < 3; ++f) {
    const std::vector<Eigen::Vector3d> here = JointPositions(skeleton, truth->poses[f]);
    const std::vector<Eigen::Vector3d> there = JointPositions(skeleton, poses[f]);
    EXPECT_NEAR(truth->poses[f][yaw], poses[f][yaw], 1e-12);
    for (size_t i = 0; i < 4; ++i) {
      Camera lab_pinhole = lab->cameras[i].calibration;
      lab_pinhole.distortion = {};
      for (size_t j = 0; j < here.size(); ++j) {
        Eigen::Vector2d p, q;
        ASSERT_TRUE(ProjectPoint(s->capture.cameras[i].calibration, here[j], &p));
        ASSERT_TRUE(ProjectPoint(lab_pinhole, there[j], &q));
        EXPECT_LT((p - q).norm(), 1e-6) << "frame " << f << " camera " << i << " joint " << j;
      }
    }
  }
}

TEST(SynthRig, RefusesWhatItCannotFilm) {
  const std::string dir = TempDir("bad");
  const std::string rig = WriteRig(dir + "/lab", Eigen::Vector3d::Zero());
  SynthOptions o;
  o.output_dir = dir + "/take";
  o.frames = 2;
  o.held_out = 0;
  o.rig_poses = dir + "/poses.json";
  StatusOr<SynthSummary> s = RunSynth(o);  // poses without a rig
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.status().message().find("--rig"), std::string::npos) << s.status().message();
  o.rig_poses.clear();
  o.rig = dir + "/nowhere";
  s = RunSynth(o);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.status().message().find("--rig"), std::string::npos) << s.status().message();
  o.rig = rig;
  o.dome = 8;
  EXPECT_FALSE(RunSynth(o).ok());
  o.dome = 0;
  o.held_out = 2;
  EXPECT_FALSE(RunSynth(o).ok());
  o.held_out = 0;
  // Fewer poses than frames asked for.
  std::vector<double> dofs(GenericDofNames().size(), 0.0);
  const nlohmann::json one = {{"dof_names", GenericDofNames()},
                              {"frames", {{{"frame", 0}, {"dofs", dofs}}}}};
  std::ofstream(dir + "/one.json") << one.dump();
  o.rig_poses = dir + "/one.json";
  s = RunSynth(o);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.status().message().find("1 frames, 2 asked"), std::string::npos)
      << s.status().message();
}

// The silhouette's centroid (pixels).
Eigen::Vector2d Centroid(const Image& silhouette) {
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  double n = 0;
  for (uint32_t y = 0; y < silhouette.height; ++y) {
    for (uint32_t x = 0; x < silhouette.width; ++x) {
      if (!silhouette.pixels[(size_t(y) * silhouette.width + x) * silhouette.channels]) continue;
      sum += Eigen::Vector2d(x, y), ++n;
    }
  }
  return n ? Eigen::Vector2d(sum / n) : Eigen::Vector2d(-1, -1);
}

TEST(SynthCalibrationError, CamerasFilmTurnedWhileTheCaptureKeepsThemAsCalibrated) {
  const std::string dir = TempDir("turned");
  SynthOptions o;
  o.cameras = 3;
  o.width = 240, o.height = 180;
  o.frames = 1;
  o.held_out = 0;
  o.texture_size = 128;
  o.output_dir = dir + "/exact";
  StatusOr<SynthSummary> exact = RunSynth(o);
  ASSERT_TRUE(exact.ok()) << exact.status().ToString();
  const double degrees = 1.0;
  o.calibration_error = degrees;
  o.output_dir = dir + "/turned";
  StatusOr<SynthSummary> turned = RunSynth(o);
  ASSERT_TRUE(turned.ok()) << turned.status().ToString();
  for (size_t c = 0; c < 3; ++c) {
    const Camera& a = exact->capture.cameras[c].calibration;
    const Camera& b = turned->capture.cameras[c].calibration;
    EXPECT_EQ(a.rotation, b.rotation);  // recorded as calibrated
    EXPECT_EQ(a.translation, b.translation);
    const std::string sil = "/truth/silhouettes/" + a.name + "/000000.png";
    StatusOr<Image> p = ReadImage(dir + "/exact" + sil), q = ReadImage(dir + "/turned" + sil);
    ASSERT_TRUE(p.ok() && q.ok());
    // A turn of the camera by a small angle moves the image of what it sees
    // by about the focal length times the angle.
    const double expected = a.fx * degrees * M_PI / 180;
    const double moved = (Centroid(*q) - Centroid(*p)).norm();
    EXPECT_NEAR(moved, expected, 0.25 * expected) << a.name;
  }
  o.calibration_error = -1;
  EXPECT_FALSE(RunSynth(o).ok());
}

}  // namespace
}  // namespace fvv
