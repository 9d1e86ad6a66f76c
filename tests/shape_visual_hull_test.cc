// The visual hull of a synthetic capture against the actor's true surface: the
// hull must contain the posed body (it is carved conservatively), and be a
// bounded multiple of its volume; the hull of another frame must not fit.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>

#include "encoder/body/kinematics.h"
#include "encoder/capture/calibration.h"
#include "encoder/capture/capture.h"
#include "encoder/encode/pose_file.h"
#include "encoder/shape/visual_hull.h"
#include "tools/synth/synth.h"

namespace fvv {
namespace {

class VisualHullTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = ::testing::TempDir() + "/visual_hull_test_" + std::to_string(getpid());
    std::system(("rm -rf '" + dir_ + "'").c_str());
    SynthOptions o;
    o.output_dir = dir_ + "/cap";
    o.cameras = 8;
    o.frames = 12;
    o.width = 320;
    o.height = 240;
    o.held_out = 0;
    o.link_silhouettes = true;
    synth_ = RunSynth(o).status();
  }
  static void TearDownTestSuite() { std::system(("rm -rf '" + dir_ + "'").c_str()); }
  void SetUp() override { ASSERT_TRUE(synth_.ok()) << synth_.ToString(); }

  // The capture's cameras and the true silhouettes of `frame`.
  static void Inputs(uint32_t frame, std::vector<Camera>* cameras, std::vector<Image>* sils) {
    auto cap = LoadCapture(dir_ + "/cap");
    ASSERT_TRUE(cap.ok()) << cap.status().ToString();
    CaptureReader reader(*cap);
    for (uint32_t c = 0; c < cap->cameras.size(); ++c) {
      cameras->push_back(cap->cameras[c].calibration);
      auto s = reader.ReadSilhouette(c, frame);
      ASSERT_TRUE(s.ok()) << s.status().ToString();
      sils->push_back(std::move(s).value());
    }
  }

  // The posed body's vertices at `frame` and its volume (closed segment meshes,
  // by the divergence theorem; overlaps at the joints counted twice).
  static std::vector<Eigen::Vector3f> Body(uint32_t frame, double* volume) {
    auto poses = LoadPoseFile(dir_ + "/cap");
    EXPECT_TRUE(poses.ok());
    const BodyModel model = MakeGenericBody(poses->shape);
    const auto skin = SkinningMatrices(model.skeleton, poses->poses[frame]);
    std::vector<Eigen::Vector3f> v = SkinPositions(model.mesh, skin);
    double vol = 0;
    for (const auto& t : model.mesh.triangles) {
      vol += v[t[0]].cast<double>().dot(v[t[1]].cast<double>().cross(v[t[2]].cast<double>())) / 6;
    }
    *volume = std::abs(vol);
    return v;
  }

  static double InsideShare(const VisualHull& hull, const std::vector<Eigen::Vector3f>& v) {
    size_t inside = 0;
    for (const auto& p : v) inside += hull.Contains(p.cast<double>());
    return double(inside) / v.size();
  }

  static std::string dir_;
  static Status synth_;
};
std::string VisualHullTest::dir_;
Status VisualHullTest::synth_;

TEST_F(VisualHullTest, ContainsTheActorAndBoundsItsVolume) {
  std::vector<Camera> cameras;
  std::vector<Image> sils;
  Inputs(0, &cameras, &sils);
  auto hull = CarveVisualHull(cameras, sils);
  ASSERT_TRUE(hull.ok()) << hull.status().ToString();
  double body_volume = 0;
  const auto body = Body(0, &body_volume);
  const auto later = Body(10, &body_volume);
  Body(0, &body_volume);
  const double inside = InsideShare(*hull, body), control = InsideShare(*hull, later);
  const double ratio = hull->Volume() / body_volume;
  std::printf(
      "  hull %zu voxels of 1 cm, %.4f m^3 = %.2fx the body's %.4f m^3; body vertices "
      "inside %.2f%% (frame 10's: %.2f%%); %zu surface voxels\n",
      hull->OccupiedCount(), hull->Volume(), ratio, body_volume, 100 * inside, 100 * control,
      hull->SurfaceVoxels().size());
  EXPECT_GT(inside, 0.995);
  EXPECT_LT(control, inside - 0.05);
  EXPECT_GT(ratio, 1.0);
  EXPECT_LT(ratio, 2.5);
}

TEST_F(VisualHullTest, RefusesMismatchedOrEmptyInputs) {
  std::vector<Camera> cameras;
  std::vector<Image> sils;
  Inputs(0, &cameras, &sils);
  std::vector<Image> fewer(sils.begin(), sils.end() - 1);
  EXPECT_EQ(CarveVisualHull(cameras, fewer).status().code(), StatusCode::kInvalidArgument);
  std::vector<Image> small = sils;
  small[3].width = 10;
  auto r = CarveVisualHull(cameras, small);
  EXPECT_NE(r.status().message().find("silhouette 3"), std::string::npos) << r.status().ToString();
  std::vector<Image> empty = sils;
  for (Image& s : empty) std::fill(s.pixels.begin(), s.pixels.end(), 0);
  r = CarveVisualHull(cameras, empty);
  EXPECT_NE(r.status().message().find("no volume in common"), std::string::npos);
  VisualHullOptions huge;
  huge.voxel_size = huge.coarse_size = 0.001;  // a studio of 1 mm voxels: refused, not allocated
  EXPECT_EQ(CarveVisualHull(cameras, sils, huge).status().code(), StatusCode::kLimitExceeded);
}

}  // namespace
}  // namespace fvv
