// Marker-free motion capture: on a short synthetic capture with
// known motion, silhouettes from background subtraction and the tracker recover
// the joints within a bound; empty silhouettes and bad inputs are flagged or
// refused, never a crash or a wild pose. Also Powell's method on its own.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "encoder/body/kinematics.h"
#include "encoder/capture/calibration.h"
#include "encoder/track/camera_choice.h"
#include "encoder/track/features.h"
#include "encoder/track/joint_truth.h"
#include "encoder/track/pose_smoothing.h"
#include "encoder/track/powell.h"
#include "encoder/track/silhouette.h"
#include "encoder/track/silhouette_calibration.h"
#include "encoder/track/track_capture.h"
#include "encoder/track/tracker.h"
#include "tools/synth/gltf_actor.h"
#include "tools/synth/synth.h"

namespace fvv {
namespace {

TEST(Powell, MinimisesWithinBounds) {
  // A curved valley (Rosenbrock); the bound x0 <= 0.5 is active at the optimum.
  auto f = [](const Eigen::VectorXd& x) {
    return 100 * std::pow(x[1] - x[0] * x[0], 2) + std::pow(1 - x[0], 2);
  };
  Eigen::VectorXd x(2), step(2), lo(2), hi(2);
  x << -1.2, 1.0;
  step << 0.2, 0.2;
  lo << -2, -2;
  hi << 0.5, 2;
  PowellOptions o;
  o.max_evaluations = 4000;
  o.max_iterations = 60;
  o.relative_tolerance = 0;
  const PowellResult r = MinimisePowell(f, &x, step, lo, hi, o);
  EXPECT_LE(x[0], 0.5);
  EXPECT_NEAR(x[0], 0.5, 0.02);
  EXPECT_NEAR(x[1], 0.25, 0.03);
  EXPECT_LT(r.value, 0.26);  // f(0.5, 0.25) = 0.25
  EXPECT_LE(r.evaluations, o.max_evaluations);
}

class TrackTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    // Each test of the suite may run as its own process at the same time.
    options_.output_dir = ::testing::TempDir() + "/track_test_" + std::to_string(getpid());
    std::system(("rm -rf '" + options_.output_dir + "'").c_str());
    options_.cameras = 6;
    options_.width = 320;
    options_.height = 240;
    options_.frames = 4;
    options_.held_out = 0;
    options_.texture_size = 512;
    options_.seed = 11;
    status_ = RunSynth(options_).status();
  }
  // Silhouettes of frame f by background subtraction against the plates.
  static std::vector<Image> Silhouettes(CaptureReader* reader, uint32_t f) {
    std::vector<Image> out;
    for (uint32_t c = 0; c < reader->capture().cameras.size(); ++c) {
      StatusOr<Image> plate = reader->ReadBackground(c), frame = reader->ReadFrame(c, f);
      EXPECT_TRUE(plate.ok() && frame.ok());
      StatusOr<Image> s = ExtractSilhouette(*frame, BackgroundModel{*plate});
      EXPECT_TRUE(s.ok());
      out.push_back(*s);
    }
    return out;
  }
  static std::vector<Camera> Cameras(const Capture& c) {
    std::vector<Camera> out;
    for (const CaptureCamera& cam : c.cameras) out.push_back(cam.calibration);
    return out;
  }
  static void TearDownTestSuite() { std::system(("rm -rf '" + options_.output_dir + "'").c_str()); }
  static SynthOptions options_;
  static Status status_;
};
SynthOptions TrackTest::options_;
Status TrackTest::status_;

TEST_F(TrackTest, RecoversKnownMotionWithinBounds) {
  ASSERT_TRUE(status_.ok()) << status_.ToString();
  StatusOr<Capture> c = LoadCapture(options_.output_dir);
  ASSERT_TRUE(c.ok());
  CaptureReader reader(*c);
  StatusOr<std::unique_ptr<Tracker>> tracker = Tracker::Create(Cameras(*c));
  ASSERT_TRUE(tracker.ok()) << tracker.status().ToString();
  std::vector<std::vector<double>> poses;
  for (uint32_t f = 0; f < c->frame_count; ++f) {
    StatusOr<FrameFit> fit = f == 0 ? (*tracker)->Initialise(Silhouettes(&reader, f))
                                    : (*tracker)->Track(Silhouettes(&reader, f));
    ASSERT_TRUE(fit.ok()) << fit.status().ToString();
    EXPECT_FALSE(fit->poor) << "frame " << f << ": " << fit->note;
    EXPECT_GT(fit->iou, 0.85) << "frame " << f;
    EXPECT_EQ(fit->cameras_used, 6);
    poses.push_back(fit->dofs);
  }
  EXPECT_NEAR((*tracker)->shape().stature, 1.0, 0.05);
  StatusOr<JointErrors> e =
      CompareWithTruth(options_.output_dir, (*tracker)->Model().skeleton, poses, 0);
  ASSERT_TRUE(e.ok()) << e.status().ToString();
  EXPECT_EQ(e->joints.size(), 17u);
  std::printf("  joint error: mean %.2f cm, max %.2f cm\n", 100 * e->mean, 100 * e->max);
  EXPECT_LT(e->mean, 0.03);
  EXPECT_LT(e->max, 0.10);
}

// The whole front end with smoothing: every frame reaches the callback once, in
// order, after the frames its smoothed pose reads, with the pose the result
// records; the smoothed poses are each the Gaussian mean of the fits' own.
TEST_F(TrackTest, SmoothedFramesReachTheCallbackInOrderWithTheirPoses) {
  ASSERT_TRUE(status_.ok()) << status_.ToString();
  TrackCaptureOptions raw_options;
  raw_options.smoothing.sigma_frames = 0;
  StatusOr<TrackCaptureResult> raw = TrackCapture(options_.output_dir, raw_options);
  ASSERT_TRUE(raw.ok()) << raw.status().ToString();
  TrackCaptureOptions o;
  o.smoothing.sigma_frames = 1;
  ASSERT_EQ(o.smoothing.Radius(), 3);
  std::vector<uint32_t> order;
  std::vector<std::vector<double>> seen;
  o.on_frame = [&](uint32_t f, const FrameFit& fit, const Tracker&,
                   const std::vector<Image>& images, const std::vector<Image>& sils) {
    EXPECT_EQ(images.size(), 6u);
    EXPECT_EQ(sils.size(), 6u);
    order.push_back(f);
    seen.push_back(fit.dofs);
    return Status::Ok();
  };
  StatusOr<TrackCaptureResult> smoothed = TrackCapture(options_.output_dir, o);
  ASSERT_TRUE(smoothed.ok()) << smoothed.status().ToString();
  ASSERT_EQ(order, (std::vector<uint32_t>{0, 1, 2, 3}));
  const std::vector<std::vector<double>> raw_poses = raw->Poses();
  std::vector<bool> angular;
  for (const DofRef& d : raw->model.skeleton.Dofs()) angular.push_back(d.kind < 3);
  double moved = 0;
  for (size_t i = 0; i < seen.size(); ++i) {
    EXPECT_EQ(seen[i], smoothed->fits[i].dofs) << "frame " << i;
    const std::vector<double> want =
        SmoothPose(raw_poses, std::vector<bool>(raw_poses.size(), true), angular, i, o.smoothing);
    ASSERT_EQ(want.size(), seen[i].size());
    for (size_t d = 0; d < want.size(); ++d) {
      EXPECT_NEAR(seen[i][d], want[d], 1e-12) << "frame " << i << " dof " << d;
      moved += std::abs(seen[i][d] - raw_poses[i][d]);
    }
    EXPECT_EQ(smoothed->fits[i].iou, raw->fits[i].iou);  // the fit's own figures
  }
  EXPECT_GT(moved, 0);
  // An error from the callback stops tracking and is returned.
  o.on_frame = [](uint32_t f, const FrameFit&, const Tracker&, const std::vector<Image>&,
                  const std::vector<Image>&) {
    return f == 1 ? InvalidArgument("stop at 1") : Status::Ok();
  };
  StatusOr<TrackCaptureResult> stopped = TrackCapture(options_.output_dir, o);
  ASSERT_FALSE(stopped.ok());
  EXPECT_EQ(stopped.status().message(), "stop at 1");
}

// Joint sightings as a keypoint network would report them, from the truth's
// joint projections: a few pixels of noise; `swapped` cameras see every
// joint's other side (a network's left-right confusion); `shift` moves every
// joint in the world before projection (sightings of a body elsewhere).
std::vector<std::vector<JointSighting>> TrueSightings(const std::string& capture_dir,
                                                      const std::vector<Camera>& cameras,
                                                      uint32_t frame, uint32_t frame_count,
                                                      const std::vector<int>& swapped = {},
                                                      const Eigen::Vector3d& shift = {0, 0, 0}) {
  StatusOr<FeatureSet> truth =
      LoadFeatures(capture_dir + "/truth/features.json", cameras, frame_count);
  EXPECT_TRUE(truth.ok()) << truth.status().ToString();
  std::vector<std::vector<JointSighting>> out(cameras.size());
  if (!truth.ok()) return out;
  const auto& points = truth->frames.at(frame);
  const auto world = TriangulateFeatures(points, cameras);
  uint32_t seed = 7 + frame;
  auto noise = [&] {
    seed = seed * 1664525u + 1013904223u;
    return (double(seed >> 8) / double(1u << 24) - 0.5) * 4.0;  // +-2 pixels
  };
  for (int j = kLeftShoulder; j < kGenericJointCount; ++j) {
    const std::string name = GenericJointName(j);
    if (!world.count(name)) continue;
    for (uint32_t c = 0; c < cameras.size(); ++c) {
      const bool swap = std::find(swapped.begin(), swapped.end(), int(c)) != swapped.end();
      std::string seen_as = name;
      if (swap) seen_as[0] = name[0] == 'l' ? 'r' : 'l';
      Eigen::Vector2d p;
      if (!ProjectPoint(cameras[c], world.at(name).position + shift, &p)) continue;
      int joint = j;
      for (int k = 0; k < kGenericJointCount; ++k) {
        if (seen_as == GenericJointName(k)) joint = k;
      }
      out[c].push_back({joint, p + Eigen::Vector2d(noise(), noise()), 0.9});
    }
  }
  return out;
}

// Sightings place the body and hold the fit: with one camera's left and right
// confused, tracking still recovers the motion, and the fit's joints lie near
// the sightings of the other cameras.
TEST_F(TrackTest, SightingsHoldTheFitWithOneCameraConfused) {
  ASSERT_TRUE(status_.ok()) << status_.ToString();
  StatusOr<Capture> c = LoadCapture(options_.output_dir);
  ASSERT_TRUE(c.ok());
  CaptureReader reader(*c);
  const std::vector<Camera> cameras = Cameras(*c);
  StatusOr<std::unique_ptr<Tracker>> tracker = Tracker::Create(cameras);
  ASSERT_TRUE(tracker.ok()) << tracker.status().ToString();
  std::vector<std::vector<double>> poses;
  for (uint32_t f = 0; f < c->frame_count; ++f) {
    const auto sightings = TrueSightings(options_.output_dir, cameras, f, c->frame_count, {1});
    StatusOr<FrameFit> fit = f == 0 ? (*tracker)->Initialise(Silhouettes(&reader, f), sightings)
                                    : (*tracker)->Track(Silhouettes(&reader, f), sightings);
    ASSERT_TRUE(fit.ok()) << fit.status().ToString();
    EXPECT_FALSE(fit->poor) << "frame " << f << ": " << fit->note;
    EXPECT_GT(fit->iou, 0.85) << "frame " << f;
    // Five cameras agree within a pixel or two; the confused one is off by
    // the body's width for the limbs it swaps.
    EXPECT_GE(fit->keypoint_distance, 0);
    EXPECT_LT(fit->keypoint_distance, 0.04) << "frame " << f;
    poses.push_back(fit->dofs);
  }
  StatusOr<JointErrors> e =
      CompareWithTruth(options_.output_dir, (*tracker)->Model().skeleton, poses, 0);
  ASSERT_TRUE(e.ok()) << e.status().ToString();
  std::printf("  joint error with sightings (one camera confused): mean %.2f cm, max %.2f cm\n",
              100 * e->mean, 100 * e->max);
  EXPECT_LT(e->mean, 0.03);
  EXPECT_LT(e->max, 0.10);
}

// Sightings of a body 40 cm away from the one the silhouettes show: the fit
// follows the silhouettes (the sightings' term is bounded), and the frame is
// flagged as disagreeing with them, not reported as a good fit.
TEST_F(TrackTest, FrameDisagreeingWithTheSightingsIsFlagged) {
  ASSERT_TRUE(status_.ok()) << status_.ToString();
  StatusOr<Capture> c = LoadCapture(options_.output_dir);
  ASSERT_TRUE(c.ok());
  CaptureReader reader(*c);
  const std::vector<Camera> cameras = Cameras(*c);
  TrackerOptions o;
  o.adapt_shape = false;
  StatusOr<std::unique_ptr<Tracker>> tracker = Tracker::Create(cameras, o);
  ASSERT_TRUE(tracker.ok());
  StatusOr<FrameFit> first = (*tracker)->Initialise(
      Silhouettes(&reader, 0), TrueSightings(options_.output_dir, cameras, 0, c->frame_count));
  ASSERT_TRUE(first.ok());
  EXPECT_FALSE(first->poor) << first->note;
  StatusOr<FrameFit> off = (*tracker)->Track(
      Silhouettes(&reader, 1),
      TrueSightings(options_.output_dir, cameras, 1, c->frame_count, {}, {0.4, 0, 0}));
  ASSERT_TRUE(off.ok());
  EXPECT_TRUE(off->poor);
  EXPECT_NE(off->note.find("disagrees with the keypoints"), std::string::npos) << off->note;
  EXPECT_GT(off->iou, 0.8);  // the silhouettes still hold the body
  EXPECT_GT(off->keypoint_distance, 0.15);
}

// A camera turned off its calibration sees the fit beside the actor by the
// same pixels in every frame: TrackCapture names that camera, and only it,
// with the shift its turn makes; on the exact calibration it names none.
TEST_F(TrackTest, NamesTheCameraWhoseCalibrationDisagrees) {
  ASSERT_TRUE(status_.ok()) << status_.ToString();
  StatusOr<Capture> exact = LoadCapture(options_.output_dir);
  ASSERT_TRUE(exact.ok());
  TrackCaptureOptions o;
  o.tracker.adapt_shape = false;
  o.shift_check_every = 1;
  o.smoothing = PoseSmoothing{0};
  StatusOr<TrackCaptureResult> r = TrackCapture(options_.output_dir, o);
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  ASSERT_EQ(r->camera_shifts.size(), exact->cameras.size());
  for (size_t c = 0; c < r->camera_shifts.size(); ++c) {
    const TrackCaptureResult::CameraShift& s = r->camera_shifts[c];
    std::printf("exact: camera %zu shift %+.1f %+.1f px (%.2f deg), IoU %.3f -> %.3f\n", c,
                s.shift.pixels.x(), s.shift.pixels.y(), s.degrees, s.shift.iou,
                s.shift.shifted_iou);
    EXPECT_EQ(s.shift.frames, int(exact->frame_count));
    EXPECT_FALSE(s.disagrees) << "camera " << c;
  }
  // Camera 2 turned 1 degree about its own vertical axis: what it sees
  // moves sideways by about fx * tan(1 degree).
  Capture turned = *exact;
  turned.directory = options_.output_dir + "/turned";
  std::system(("mkdir -p '" + turned.directory + "'").c_str());
  for (CaptureCamera& cam : turned.cameras) {
    cam.frames.path = options_.output_dir + "/" + cam.frames.path;
    if (cam.background) cam.background = options_.output_dir + "/" + *cam.background;
    if (cam.silhouettes) cam.silhouettes->path = options_.output_dir + "/" + cam.silhouettes->path;
  }
  Camera& cam = turned.cameras[2].calibration;
  const Eigen::Matrix3d rotation =
      Eigen::AngleAxisd(1.0 * M_PI / 180, Eigen::Vector3d::UnitY()) * CameraRotation(cam);
  const Eigen::Vector3d t = -rotation * CameraCentre(cam);
  for (int i = 0; i < 9; ++i) cam.rotation[size_t(i)] = rotation(i / 3, i % 3);
  for (int i = 0; i < 3; ++i) cam.translation[size_t(i)] = t[i];
  ASSERT_TRUE(SaveCapture(turned).ok());
  StatusOr<TrackCaptureResult> t2 = TrackCapture(turned.directory, o);
  ASSERT_TRUE(t2.ok()) << t2.status().ToString();
  const double expected = cam.fx * std::tan(1.0 * M_PI / 180);
  for (size_t c = 0; c < t2->camera_shifts.size(); ++c) {
    const TrackCaptureResult::CameraShift& s = t2->camera_shifts[c];
    std::printf("camera 2 turned: camera %zu shift %+.1f %+.1f px (%.2f deg), IoU %.3f -> %.3f\n",
                c, s.shift.pixels.x(), s.shift.pixels.y(), s.degrees, s.shift.iou,
                s.shift.shifted_iou);
    EXPECT_EQ(s.disagrees, c == 2) << "camera " << c;
  }
  // The fit follows the five cameras that agree: the turned one sees most
  // of its turn.
  const Eigen::Vector2d s2 = t2->camera_shifts[2].shift.pixels;
  EXPECT_GT(std::abs(s2.x()), 0.6 * expected);
  EXPECT_LT(std::abs(s2.x()), 1.3 * expected);
  EXPECT_LT(std::abs(s2.y()), 0.3 * expected);
  const std::string json = t2->ToJson();
  EXPECT_NE(json.find("\"calibration_disagrees\": true"), std::string::npos);
}

// Of a 32-camera dome the fit takes 10 that see the whole volume (no
// close-up) and stand apart: around the actor and over the rings' heights.
TEST(CameraChoice, ASpreadFewOfADomeSeeingTheActorWhole) {
  const std::vector<Camera> dome = MakeDomeCameras(32, 640, 360);
  ASSERT_EQ(dome.size(), 32u);
  const Eigen::Vector3d centre = CaptureVolumeCentre(dome);
  EXPECT_LT((centre - Eigen::Vector3d(0, 0.9, 0)).norm(), 0.35) << centre.transpose();
  const CameraChoice choice = ChooseTrackingCameras(dome, 10);
  ASSERT_EQ(choice.cameras.size(), 10u);
  EXPECT_TRUE(std::is_sorted(choice.cameras.begin(), choice.cameras.end()));
  int close_ups = 0, whole = 0;
  for (uint32_t c = 0; c < dome.size(); ++c) {
    close_ups += dome[c].fx > 1.5 * 1.5 * 360;
    whole += choice.coverage[c] >= 1.0;
  }
  EXPECT_GE(close_ups, 4);
  EXPECT_GE(whole, 20);
  std::vector<Eigen::Vector3d> dirs;
  double lowest = 1e9, highest = -1e9;
  for (uint32_t c : choice.cameras) {
    EXPECT_GE(choice.coverage[c], 1.0) << dome[c].name << " does not see the volume whole";
    EXPECT_LT(dome[c].fx, 1.5 * 1.5 * 360) << dome[c].name << " is a close-up";
    dirs.push_back((CameraCentre(dome[c]) - choice.centre).normalized());
    lowest = std::min(lowest, CameraCentre(dome[c]).y());
    highest = std::max(highest, CameraCentre(dome[c]).y());
  }
  EXPECT_LT(lowest, 1.0);   // from the low ring
  EXPECT_GT(highest, 2.0);  // and from above
  // Spread: no two chosen cameras within 20 degrees of each other, seen from
  // the volume's centre; and around it, every quarter holds one.
  for (size_t i = 0; i < dirs.size(); ++i) {
    for (size_t j = i + 1; j < dirs.size(); ++j) {
      EXPECT_GT(std::acos(std::clamp(dirs[i].dot(dirs[j]), -1.0, 1.0)) * 180 / M_PI, 20.0)
          << dome[choice.cameras[i]].name << " " << dome[choice.cameras[j]].name;
    }
  }
  bool quarter[4] = {false, false, false, false};
  for (const Eigen::Vector3d& d : dirs) {
    const double a = std::atan2(d.x(), d.z());
    quarter[int(std::floor((a + M_PI) / (M_PI / 2))) & 3] = true;
  }
  for (int q = 0; q < 4; ++q) EXPECT_TRUE(quarter[q]) << "quarter " << q;
  // A rig no larger than the count: every camera.
  EXPECT_EQ(ChooseTrackingCameras(MakeStudioCameras(8, 640, 480, 0, "c"), 10).cameras.size(), 8u);
}

// The turn TurnedByImageShift makes moves what the camera sees at the
// principal point by the pixels asked, and points near it by nearly as much.
TEST(SilhouetteCalibration, ATurnMovesTheImageByTheShiftAsked) {
  const Camera c = LookAtCamera("c", 640, 480, 600, Eigen::Vector3d(3, 1.5, 2),
                                Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(0, 1, 0));
  const Eigen::Vector2d shift(12, -7);
  const Camera turned = TurnedByImageShift(c, shift);
  for (const Eigen::Vector2d& at : {Eigen::Vector2d(c.cx, c.cy), Eigen::Vector2d(400, 300)}) {
    const Eigen::Vector3d point = UnprojectPixel(c, at, 3.0);
    Eigen::Vector2d moved;
    ASSERT_TRUE(ProjectPoint(turned, point, &moved));
    EXPECT_NEAR((moved - at - shift).norm(), 0, at == Eigen::Vector2d(c.cx, c.cy) ? 0.05 : 0.5)
        << moved.transpose();
  }
  EXPECT_NEAR((CameraCentre(turned) - CameraCentre(c)).norm(), 0, 1e-9);  // turned, not moved
  EXPECT_NEAR(TurnBetween(c, turned), std::atan(shift.norm() / 600) * 180 / M_PI, 0.01);
}

// Two cameras turned off their calibration (1 degree and 0.7 degree about
// different axes) are turned back by the outlines of the actor tracked with
// every camera; the cameras that agreed stay where they were.
TEST_F(TrackTest, SilhouetteRefinementTurnsBumpedCamerasBack) {
  ASSERT_TRUE(status_.ok()) << status_.ToString();
  StatusOr<Capture> exact = LoadCapture(options_.output_dir);
  ASSERT_TRUE(exact.ok());
  Capture bumped = *exact;
  for (CaptureCamera& cam : bumped.cameras) {
    cam.frames.path = options_.output_dir + "/" + cam.frames.path;
    if (cam.background) cam.background = options_.output_dir + "/" + *cam.background;
    if (cam.silhouettes) cam.silhouettes->path = options_.output_dir + "/" + cam.silhouettes->path;
  }
  auto turn = [](Camera* cam, double degrees, const Eigen::Vector3d& axis) {
    const Eigen::Matrix3d r = Eigen::AngleAxisd(degrees * M_PI / 180, axis) * CameraRotation(*cam);
    const Eigen::Vector3d t = -r * CameraCentre(*cam);
    for (int i = 0; i < 9; ++i) cam->rotation[size_t(i)] = r(i / 3, i % 3);
    for (int i = 0; i < 3; ++i) cam->translation[size_t(i)] = t[i];
  };
  turn(&bumped.cameras[2].calibration, 1.0, Eigen::Vector3d::UnitY());
  turn(&bumped.cameras[5].calibration, 0.7, Eigen::Vector3d::UnitX());
  SilhouetteCalibrationOptions o;
  o.first = 0;
  o.last = 3;
  o.rounds = 3;
  o.track.tracker.adapt_shape = false;
  o.track.smoothing = PoseSmoothing{0};
  StatusOr<SilhouetteCalibration> r = RefineCamerasFromSilhouettes(bumped, o);
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  ASSERT_EQ(r->cameras.size(), exact->cameras.size());
  for (size_t c = 0; c < r->cameras.size(); ++c) {
    const double before = TurnBetween(bumped.cameras[c].calibration, exact->cameras[c].calibration);
    const double after = TurnBetween(r->cameras[c], exact->cameras[c].calibration);
    std::printf("camera %zu: %.2f degrees off before, %.2f after (turned %.2f)\n", c, before, after,
                r->turn_deg[c]);
    EXPECT_LT(after, 0.3) << "camera " << c;
    EXPECT_NEAR(CameraCentre(r->cameras[c])[0], CameraCentre(exact->cameras[c].calibration)[0],
                1e-9);
  }
  // The fit agrees better with the outlines in the last round than the first.
  EXPECT_GT(r->rounds.back().mean_iou, r->rounds.front().mean_iou);
  // A span too short for a shift is refused.
  o.last = 1;
  EXPECT_FALSE(RefineCamerasFromSilhouettes(bumped, o).ok());
}

TEST_F(TrackTest, EmptyOrMissingSilhouettesAreFlaggedNotWild) {
  ASSERT_TRUE(status_.ok()) << status_.ToString();
  StatusOr<Capture> c = LoadCapture(options_.output_dir);
  ASSERT_TRUE(c.ok());
  CaptureReader reader(*c);
  TrackerOptions o;
  o.adapt_shape = false;
  StatusOr<std::unique_ptr<Tracker>> tracker = Tracker::Create(Cameras(*c), o);
  ASSERT_TRUE(tracker.ok());
  std::vector<Image> empty = Silhouettes(&reader, 0);
  for (Image& s : empty) std::fill(s.pixels.begin(), s.pixels.end(), 0);
  // Initialising without the actor in view is refused with a message.
  StatusOr<FrameFit> init = (*tracker)->Initialise(empty);
  ASSERT_FALSE(init.ok());
  EXPECT_NE(init.status().message().find("at least 2 cameras"), std::string::npos);
  StatusOr<FrameFit> first = (*tracker)->Initialise(Silhouettes(&reader, 0));
  ASSERT_TRUE(first.ok());
  // A frame with nothing in view: flagged, pose predicted (finite, within limits).
  StatusOr<FrameFit> blind = (*tracker)->Track(empty);
  ASSERT_TRUE(blind.ok());
  EXPECT_TRUE(blind->poor);
  EXPECT_NE(blind->note.find("no silhouette"), std::string::npos);
  const BodyModel model = (*tracker)->Model();
  const std::vector<double> clamped = ClampToLimits(model.skeleton, blind->dofs);
  for (size_t d = 0; d < clamped.size(); ++d) {
    ASSERT_TRUE(std::isfinite(blind->dofs[d]));
    EXPECT_EQ(clamped[d], blind->dofs[d]);
  }
  const double drift =
      std::abs(blind->dofs[0] - first->dofs[0]) + std::abs(blind->dofs[2] - first->dofs[2]);
  EXPECT_LT(drift, 0.2);
  // Only one camera sees the actor: flagged.
  std::vector<Image> one = empty;
  one[2] = Silhouettes(&reader, 1)[2];
  StatusOr<FrameFit> single = (*tracker)->Track(one);
  ASSERT_TRUE(single.ok());
  EXPECT_TRUE(single->poor);
  // Wrong inputs: a camera's silhouette missing, or of the wrong size.
  std::vector<Image> fewer = Silhouettes(&reader, 1);
  fewer.pop_back();
  EXPECT_FALSE((*tracker)->Track(fewer).ok());
  std::vector<Image> wrong = Silhouettes(&reader, 1);
  wrong[1].width /= 2;
  wrong[1].pixels.resize(wrong[1].pixels.size() / 2);
  StatusOr<FrameFit> w = (*tracker)->Track(wrong);
  ASSERT_FALSE(w.ok());
  EXPECT_NE(w.status().message().find("cam01"), std::string::npos) << w.status().message();
}

// A character far from the generic body's proportions (CesiumMan: a head
// twice as wide, short legs, narrow shoulders) is fitted with proportions of
// its own: initialised from one frame, its joints land far closer to the truth
// than with the generic proportions scaled to its height.
// CesiumMan (a cartoon body, third-party data) rendered by fvv synth with its
// silhouettes: `frames` frames, 8 cameras. Skips when the model is absent.
class CesiumManTest : public ::testing::Test {
 protected:
  void Make(uint32_t frames) {
    const char* env = std::getenv("FVV_TEST_DATA");
    const std::string actor = std::string(env ? env : FVV_TEST_DATA_DIR) + "/models/CesiumMan.glb";
    struct stat st;
    if (stat(actor.c_str(), &st) != 0) GTEST_SKIP() << actor << " absent (third-party data)";
    SynthOptions s;
    s.output_dir = dir_ = ::testing::TempDir() + "/track_test_cesium_" + std::to_string(getpid());
    std::system(("rm -rf '" + s.output_dir + "'").c_str());
    s.actor = actor_ = actor;
    s.cameras = 8;
    s.frames = frames;
    s.held_out = 0;
    s.link_silhouettes = true;
    ASSERT_TRUE(RunSynth(s).ok());
    StatusOr<Capture> c = LoadCapture(s.output_dir);
    ASSERT_TRUE(c.ok());
    CaptureReader reader(*c);
    sils_.assign(frames, {});
    for (uint32_t k = 0; k < c->cameras.size(); ++k) {
      cameras_.push_back(c->cameras[k].calibration);
      for (uint32_t f = 0; f < frames; ++f) {
        StatusOr<Image> sil = reader.ReadSilhouette(k, f);
        ASSERT_TRUE(sil.ok()) << sil.status().ToString();
        sils_[f].push_back(*sil);
      }
    }
  }
  void TearDown() override {
    if (!dir_.empty()) std::system(("rm -rf '" + dir_ + "'").c_str());
  }
  std::string dir_, actor_;
  std::vector<Camera> cameras_;
  std::vector<std::vector<Image>> sils_;  // [frame][camera]
};

TEST_F(CesiumManTest, ActorWithOtherProportionsGetsItsOwn) {
  Make(1);
  if (IsSkipped() || HasFatalFailure()) return;
  double error[2] = {0, 0};
  BodyShape shape[2];
  for (int own = 0; own < 2; ++own) {
    TrackerOptions o;
    o.proportions_iou = own ? 0.85 : 0.0;  // 0: never leave the generic proportions
    StatusOr<std::unique_ptr<Tracker>> tracker = Tracker::Create(cameras_, o);
    ASSERT_TRUE(tracker.ok());
    StatusOr<FrameFit> fit = (*tracker)->Initialise(sils_[0]);
    ASSERT_TRUE(fit.ok()) << fit.status().ToString();
    StatusOr<JointErrors> e = CompareWithTruth(dir_, (*tracker)->Model().skeleton, {fit->dofs}, 0);
    ASSERT_TRUE(e.ok()) << e.status().ToString();
    EXPECT_EQ(e->joints.size(), 13u);
    error[own] = e->mean;
    shape[own] = (*tracker)->shape();
    if (own) {
      // The model as posed reaches as high as the actor's head: its height
      // is matched in the pose (CesiumMan walks, knees bent), not standing.
      const BodyModel model = (*tracker)->Model();
      double top = -1e30, actor_top = -1e30;
      for (const Eigen::Vector3f& p :
           SkinPositions(model.mesh, SkinningMatrices(model.skeleton, fit->dofs))) {
        top = std::max(top, double(p.y()));
      }
      StatusOr<std::unique_ptr<GltfActor>> actor = GltfActor::Load(actor_, 25, 1);
      ASSERT_TRUE(actor.ok()) << actor.status().ToString();
      for (const Eigen::Vector3f& p : (*actor)->PosedPositions(0))
        actor_top = std::max(actor_top, double(p.y()));
      std::printf("  own proportions: model top %.3f m, actor top %.3f m\n", top, actor_top);
      EXPECT_NEAR(top, actor_top, 0.02);
    }
    std::printf("  %s proportions: IoU %.3f, mean joint error %.1f cm\n", own ? "own" : "generic",
                fit->iou, 100 * e->mean);
  }
  EXPECT_LT(error[1], 0.10);
  EXPECT_LT(error[1], 0.5 * error[0]);
  // The large head is seen as one: over twice as wide as the generic body's,
  // scaled (the head's range goes beyond other segments' 2).
  std::printf("  own head: length %.2f, girth %.2f\n", shape[1].length[kSegHead],
              shape[1].girth[kSegHead]);
  EXPECT_GT(shape[1].girth[kSegHead], 2.2);
}

// The first frame's arms, hanging in front of the trunk, are fitted short;
// refitted over later frames, where they swing, they lengthen, and the
// silhouettes fit better. (The joint errors this brings are measured by
// track_bench over 50 frames: 8.3 -> 5.9 cm.)
TEST_F(CesiumManTest, ArmLengthRefittedOverTrackedFrames) {
  constexpr uint32_t kFrames = 9;
  Make(kFrames);
  if (IsSkipped() || HasFatalFailure()) return;
  double arms[2] = {0, 0}, limb_error[2] = {0, 0}, last_iou[2] = {0, 0};
  for (int refit = 0; refit < 2; ++refit) {
    TrackerOptions o;
    o.arm_refit_frames = refit ? 4 : 0;
    o.arm_refit_spacing = 2;  // frames 2, 4, 6 and 8
    StatusOr<std::unique_ptr<Tracker>> tracker = Tracker::Create(cameras_, o);
    ASSERT_TRUE(tracker.ok());
    std::vector<std::vector<double>> poses;
    for (uint32_t f = 0; f < kFrames; ++f) {
      StatusOr<FrameFit> fit = (*tracker)->Track(sils_[f]);
      ASSERT_TRUE(fit.ok()) << fit.status().ToString();
      poses.push_back(fit->dofs);
      last_iou[refit] = fit->iou;
    }
    arms[refit] = (*tracker)->shape().length[kSegLeftUpperArm];
    // The last frame, tracked with the refitted arms: elbows and wrists.
    StatusOr<JointErrors> e =
        CompareWithTruth(dir_, (*tracker)->Model().skeleton, {poses.back()}, kFrames - 1);
    ASSERT_TRUE(e.ok()) << e.status().ToString();
    for (size_t k = 0; k < e->joints.size(); ++k) {
      const std::string& j = e->joints[k];
      if (j.find("elbow") != std::string::npos || j.find("wrist") != std::string::npos)
        limb_error[refit] += e->per_joint_mean[k] / 4;
    }
    std::printf(
        "  arm refit %s: arm length %.2f, last frame: IoU %.3f, elbows and wrists %.1f cm\n",
        refit ? "on" : "off", arms[refit], last_iou[refit], 100 * limb_error[refit]);
  }
  EXPECT_GT(arms[1], arms[0] + 0.08);
  EXPECT_GT(last_iou[1], last_iou[0] + 0.003);
}

// Half a stride after the first frame, the prediction (the first frame's
// legs) has the wrong leg forward; reaching each foot with the other leg, the
// legs crossed, fits the silhouettes nearly as well. Trying the legs' angles
// exchanged finds the stride's right phase.
TEST_F(CesiumManTest, LegsExchangedFindTheStridesPhase) {
  constexpr uint32_t kFrames = 13;
  Make(kFrames);
  if (IsSkipped() || HasFatalFailure()) return;
  double legs[2] = {0, 0};
  for (int exchange = 0; exchange < 2; ++exchange) {
    TrackerOptions o;
    o.exchange_legs = exchange;
    o.arm_refit_frames = 0;
    StatusOr<std::unique_ptr<Tracker>> tracker = Tracker::Create(cameras_, o);
    ASSERT_TRUE(tracker.ok());
    ASSERT_TRUE((*tracker)->Initialise(sils_[0]).ok());
    StatusOr<FrameFit> fit = (*tracker)->Track(sils_[kFrames - 1]);
    ASSERT_TRUE(fit.ok()) << fit.status().ToString();
    StatusOr<JointErrors> e =
        CompareWithTruth(dir_, (*tracker)->Model().skeleton, {fit->dofs}, kFrames - 1);
    ASSERT_TRUE(e.ok()) << e.status().ToString();
    for (size_t k = 0; k < e->joints.size(); ++k) {
      const std::string& j = e->joints[k];
      if (j.find("knee") != std::string::npos || j.find("ankle") != std::string::npos)
        legs[exchange] += e->per_joint_mean[k] / 4;
    }
    std::printf("  legs exchanged %s: IoU %.3f, knees and ankles %.1f cm\n",
                exchange ? "on" : "off", fit->iou, 100 * legs[exchange]);
  }
  EXPECT_LT(legs[1], 0.08);
  EXPECT_GT(legs[0], legs[1] + 0.10);  // the jump does cross the legs without it
}

// Smoothing keeps what it must keep (constants, straight lines away from the
// ends, angles across +-pi) and removes jitter, ignoring flagged fits.
TEST(PoseSmoothing, KeepsMotionAndRemovesJitter) {
  const double kPi = 3.14159265358979323846;
  const PoseSmoothing off{0}, on{1.5};
  EXPECT_EQ(off.Radius(), 0);
  EXPECT_EQ(on.Radius(), 4);
  const std::vector<bool> angular{true, false};
  // Off: the pose itself, bit for bit.
  const std::vector<std::vector<double>> few{{0.1, 2}, {0.3, -1}, {0.2, 5}};
  EXPECT_EQ(SmoothPose(few, {}, angular, 1, off), few[1]);
  // A constant stays constant, ends included; a straight line stays straight
  // where the window is whole.
  std::vector<std::vector<double>> line, jitter;
  const double e = 0.05;
  for (int i = 0; i < 20; ++i) {
    line.push_back({0.5, 0.1 * i});
    jitter.push_back({0.02 * i + (i % 2 ? e : -e), 1.0});
  }
  for (size_t i = 0; i < line.size(); ++i) {
    const std::vector<double> p = SmoothPose(line, {}, angular, i, on);
    EXPECT_NEAR(p[0], 0.5, 1e-12);
    if (i >= 4 && i + 4 < line.size()) {
      EXPECT_NEAR(p[1], 0.1 * double(i), 1e-9) << i;
    }
  }
  // Alternating jitter of +-e around a ramp: most of it goes.
  for (size_t i = 4; i + 4 < jitter.size(); ++i) {
    const std::vector<double> p = SmoothPose(jitter, {}, angular, i, on);
    EXPECT_LT(std::abs(p[0] - 0.02 * double(i)), e / 10) << i;
    EXPECT_NEAR(p[1], 1.0, 1e-12);
  }
  // An angle crossing +-pi stays near +-pi (a plain mean would give about 0).
  const std::vector<std::vector<double>> wrap{
      {kPi - 0.02, 0}, {-kPi + 0.02, 0}, {kPi - 0.01, 0}, {-kPi + 0.01, 0}};
  for (size_t i = 0; i < wrap.size(); ++i) {
    const double a = SmoothPose(wrap, {}, angular, i, on)[0];
    EXPECT_LT(std::abs(std::remainder(a - kPi, 2 * kPi)), 0.03) << i << ": " << a;
  }
  // A flagged fit does not pull its neighbours, but keeps its own value in.
  std::vector<std::vector<double>> outlier(9, {0.0, 0.0});
  outlier[4] = {1.0, 10.0};
  std::vector<bool> trusted(9, true);
  trusted[4] = false;
  EXPECT_EQ(SmoothPose(outlier, trusted, angular, 3, on), (std::vector<double>{0, 0}));
  EXPECT_GT(SmoothPose(outlier, trusted, angular, 4, on)[1], 0.0);
  EXPECT_GT(SmoothPose(outlier, {}, angular, 3, on)[1], 0.5);  // trusted, it would
}

TEST(Tracker, RejectsBrokenCalibration) {
  std::vector<Camera> cams = MakeStudioCameras(2, 64, 48, 0, "c");
  cams[1].rotation[0] = 3;
  EXPECT_FALSE(Tracker::Create(cams).ok());
  EXPECT_FALSE(Tracker::Create({}).ok());
}

}  // namespace
}  // namespace fvv
