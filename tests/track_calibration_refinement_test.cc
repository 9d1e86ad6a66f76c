// Camera poses refined from joint sightings: cameras knocked off their
// calibration come back to agreeing with each other on frames the refinement
// never saw; a calibration already right stays put; wrong input is refused.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "encoder/body/generic_body.h"
#include "encoder/capture/calibration.h"
#include "encoder/track/calibration_refinement.h"
#include "encoder/track/camera_sync.h"

namespace fvv {
namespace {

using Sightings = std::vector<std::vector<std::vector<JointSighting>>>;

// Four portrait cameras around a person-sized volume, as in a small lab.
std::vector<Camera> Ring() {
  std::vector<Camera> cameras;
  for (int i = 0; i < 4; ++i) {
    const double a = 0.4 + i * 1.45;
    const Eigen::Vector3d centre(3.2 * std::cos(a), 3.2 * std::sin(a), 1.6 + 0.15 * i);
    Camera c = LookAtCamera("cam" + std::to_string(i), 1080, 1920, 1700, centre,
                            Eigen::Vector3d(0, 0, 1.0), Eigen::Vector3d(0, 0, 1));
    c.distortion = {-0.05, 0.01, 0, 0, 0};
    cameras.push_back(c);
  }
  return cameras;
}

// `frames` frames of 12 joints of a body-sized cloud moving about, seen by
// every camera with `noise_px` of keypoint noise; with `wild`, one sighting
// in forty is another joint's place.
Sightings Sight(const std::vector<Camera>& cameras, int frames, double noise_px, uint32_t seed,
                bool wild_ones = true) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::normal_distribution<double> noise(0, noise_px);
  Sightings all;
  for (int f = 0; f < frames; ++f) {
    const Eigen::Vector3d body(0.4 * u(rng), 0.4 * u(rng), 0);
    std::vector<Eigen::Vector3d> joints;
    for (int j = kLeftShoulder; j <= kRightAnkle; ++j) {
      joints.push_back(body + Eigen::Vector3d(0.25 * u(rng), 0.2 * u(rng), 0.9 + 0.75 * u(rng)));
    }
    std::vector<std::vector<JointSighting>> frame(cameras.size());
    for (size_t c = 0; c < cameras.size(); ++c) {
      for (size_t j = 0; j < joints.size(); ++j) {
        JointSighting s;
        s.joint = kLeftShoulder + int(j);
        const bool wild = wild_ones && rng() % 40 == 0;
        if (!ProjectPoint(cameras[c], joints[wild ? (j + 3) % joints.size() : j], &s.pixel)) {
          continue;
        }
        s.pixel += Eigen::Vector2d(noise(rng), noise(rng));
        s.confidence = 0.9;
        frame[c].push_back(s);
      }
    }
    all.push_back(frame);
  }
  return all;
}

// Each camera turned by `degrees` about a random axis and moved by `metres`.
std::vector<Camera> Knock(std::vector<Camera> cameras, double degrees, double metres,
                          uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0, 1);
  for (Camera& c : cameras) {
    const Eigen::Vector3d axis = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
    const Eigen::Vector3d move = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized() * metres;
    const Eigen::Matrix3d r =
        Eigen::AngleAxisd(degrees * 3.14159265358979 / 180, axis).toRotationMatrix() *
        CameraRotation(c);
    const Eigen::Vector3d t = -r * (CameraCentre(c) + move);
    for (int i = 0; i < 9; ++i) c.rotation[size_t(i)] = r(i / 3, i % 3);
    for (int i = 0; i < 3; ++i) c.translation[size_t(i)] = t[i];
  }
  return cameras;
}

// Mean over frames and cameras of each camera's sightings against the other
// cameras' triangulated: what tracking in a held-out camera would meet.
double HeldOutAgreement(const std::vector<Camera>& cameras, const Sightings& sightings) {
  double sum = 0;
  int n = 0;
  for (const auto& frame : sightings) {
    for (uint32_t k = 0; k < cameras.size(); ++k) {
      const double v = KeypointAgreement(cameras, k, frame, 1e6);
      if (v >= 0) sum += v, ++n;
    }
  }
  return sum / n;
}

TEST(CalibrationRefinement, KnockedCamerasAgreeAgainOnFramesItNeverSaw) {
  const std::vector<Camera> truth = Ring();
  const std::vector<Camera> knocked = Knock(truth, 0.6, 0.03, 7);
  const Sightings fit = Sight(truth, 40, 2.0, 1), check = Sight(truth, 20, 0.0, 2, false);
  StatusOr<CalibrationRefinement> r = RefineCameraPoses(knocked, fit);
  ASSERT_TRUE(r.ok()) << r.status().message();
  const double before = HeldOutAgreement(knocked, check),
               after = HeldOutAgreement(r->cameras, check), exact = HeldOutAgreement(truth, check);
  EXPECT_GT(before, 8.0);  // the knock matters
  EXPECT_LT(after, 1.0) << "before " << before << ", true calibration " << exact;
  ASSERT_EQ(r->cameras.size(), 4u);
  for (size_t c = 0; c < 4; ++c) {
    EXPECT_LT(r->after_px[c], 0.6 * r->before_px[c]);
    EXPECT_LT(r->after_px[c], 3.0);  // keypoint noise 2 px per axis
    EXPECT_GT(r->sightings[c], 400u);
    EXPECT_EQ(r->cameras[c].name, knocked[c].name);
    EXPECT_EQ(r->cameras[c].fx, knocked[c].fx);
    EXPECT_EQ(r->cameras[c].distortion, knocked[c].distortion);
    EXPECT_LT(r->rotation_deg[c], 2.0);
    EXPECT_LT(r->centre_m[c], 0.15);
  }
}

TEST(CalibrationRefinement, ARightCalibrationStaysPut) {
  const std::vector<Camera> truth = Ring();
  StatusOr<CalibrationRefinement> r = RefineCameraPoses(truth, Sight(truth, 40, 2.0, 3));
  ASSERT_TRUE(r.ok()) << r.status().message();
  for (size_t c = 0; c < 4; ++c) {
    EXPECT_LT(r->rotation_deg[c], 0.1);  // a sixth of the knock above
    EXPECT_LT(r->centre_m[c], 0.01);
  }
}

TEST(CalibrationRefinement, RefusesTooLittleToGoOn) {
  const std::vector<Camera> truth = Ring();
  StatusOr<CalibrationRefinement> few = RefineCameraPoses(truth, Sight(truth, 1, 1.0, 4));
  ASSERT_FALSE(few.ok());
  EXPECT_NE(few.status().message().find("needs 20"), std::string::npos) << few.status().message();
  const std::vector<Camera> one(1, truth[0]);
  EXPECT_FALSE(RefineCameraPoses(one, Sight(one, 40, 1.0, 5)).ok());
  Sightings mismatched = Sight(truth, 40, 1.0, 6);
  mismatched[3].pop_back();
  StatusOr<CalibrationRefinement> bad = RefineCameraPoses(truth, mismatched);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.status().message().find("sightings of 3 cameras"), std::string::npos);
}

}  // namespace
}  // namespace fvv
