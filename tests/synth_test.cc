// fvv synth: the generator's output agrees with its own ground truth
// (silhouettes equal the projected posed mesh within a pixel; joints are the
// body model's), images look like a capture (actor differs from the plate only
// inside its silhouette and shadow), and output is deterministic for a seed.
#include "tools/synth/synth.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>

#include "encoder/body/kinematics.h"
#include "encoder/capture/calibration.h"
#include "encoder/track/silhouette.h"

namespace fvv {
namespace {

// Pixels whose centres fall inside some projected triangle (the rule GL uses).
std::vector<uint8_t> ProjectMesh(const Camera& cam, const std::vector<Eigen::Vector3f>& posed,
                                 const std::vector<uint32_t>& indices) {
  std::vector<uint8_t> mask(size_t{cam.width} * cam.height, 0);
  std::vector<Eigen::Vector2d> px(posed.size());
  for (size_t v = 0; v < posed.size(); ++v) ProjectPoint(cam, posed[v].cast<double>(), &px[v]);
  for (size_t t = 0; t + 2 < indices.size(); t += 3) {
    const Eigen::Vector2d a = px[indices[t]], b = px[indices[t + 1]], c = px[indices[t + 2]];
    const double area = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
    if (std::abs(area) < 1e-12) continue;
    const int x0 = std::max(0, int(std::floor(std::min({a.x(), b.x(), c.x()}))));
    const int x1 = std::min(int(cam.width) - 1, int(std::ceil(std::max({a.x(), b.x(), c.x()}))));
    const int y0 = std::max(0, int(std::floor(std::min({a.y(), b.y(), c.y()}))));
    const int y1 = std::min(int(cam.height) - 1, int(std::ceil(std::max({a.y(), b.y(), c.y()}))));
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const Eigen::Vector2d q(x, y);
        const double w0 = ((c - b).x() * (q - b).y() - (c - b).y() * (q - b).x()) / area;
        const double w1 = ((a - c).x() * (q - c).y() - (a - c).y() * (q - c).x()) / area;
        if (w0 >= 0 && w1 >= 0 && w0 + w1 <= 1) mask[size_t(y) * cam.width + x] = 1;
      }
    }
  }
  return mask;
}

// Every pixel where a and b disagree has a pixel within one step (8-neighbourhood)
// where they agree with the other mask's value: the masks differ only along edges.
int DisagreementsBeyondOnePixel(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b, int w,
                                int h) {
  int bad = 0;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      if (a[i] == b[i]) continue;
      bool near = false;  // a's value occurs in b nearby (an edge shifted by at most one pixel)
      for (int dy = -1; dy <= 1 && !near; ++dy) {
        for (int dx = -1; dx <= 1 && !near; ++dx) {
          const int nx = x + dx, ny = y + dy;
          if (nx >= 0 && ny >= 0 && nx < w && ny < h) near = b[size_t(ny) * w + nx] == a[i];
        }
      }
      bad += !near;
    }
  }
  return bad;
}

class SynthTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    // ctest runs each test of the suite as its own process, possibly at the
    // same time: each process renders into its own directory.
    dir_ = ::testing::TempDir() + "/synth_test_" + std::to_string(getpid());
    std::system(("rm -rf '" + dir_ + "'").c_str());
    options_.output_dir = dir_;
    options_.cameras = 3;
    options_.width = 200;
    options_.height = 150;
    options_.frames = 4;
    options_.held_out = 1;
    options_.texture_size = 256;
    options_.noise = 2.0;
    options_.seed = 5;
    result_ = RunSynth(options_).status();
  }
  static void TearDownTestSuite() {
    std::system(("rm -rf '" + dir_ + "' '" + dir_ + "_again' '" + dir_ + "_other'").c_str());
  }
  static std::string dir_;
  static SynthOptions options_;
  static Status result_;
};
std::string SynthTest::dir_;
SynthOptions SynthTest::options_;
Status SynthTest::result_;

TEST_F(SynthTest, WritesALoadableCaptureWithTruth) {
  ASSERT_TRUE(result_.ok()) << result_.ToString();
  StatusOr<Capture> c = LoadCapture(dir_);
  ASSERT_TRUE(c.ok()) << c.status().ToString();
  EXPECT_EQ(c->cameras.size(), 3u);
  EXPECT_EQ(c->frame_count, 4u);
  CaptureReader reader(*c);
  EXPECT_TRUE(reader.CheckFiles().ok());
  EXPECT_TRUE(reader.HasBackgrounds());
  StatusOr<Capture> held = LoadCapture(dir_ + "/truth/heldout");
  ASSERT_TRUE(held.ok()) << held.status().ToString();
  EXPECT_EQ(held->cameras.size(), 1u);
  std::ifstream in(dir_ + "/truth/truth.json");
  const nlohmann::json truth = nlohmann::json::parse(in);
  ASSERT_EQ(truth["frames"].size(), 4u);
  EXPECT_EQ(truth["frames"][0]["joints"].size(), 17u);
  EXPECT_EQ(truth["frames"][0]["dofs"].size(), 35u);
  EXPECT_EQ(truth["dof_names"].size(), 35u);
}

// The true silhouettes of a synthetic capture against the actor's posed mesh
// projected on the CPU, for frames `frames` of every camera.
void ExpectSilhouettesMatchMesh(const std::string& dir, const Actor& actor,
                                const std::vector<uint32_t>& frames) {
  StatusOr<Capture> c = LoadCapture(dir);
  ASSERT_TRUE(c.ok()) << c.status().ToString();
  for (const auto& cam : c->cameras) {
    for (uint32_t f : frames) {
      char name[128];
      std::snprintf(name, sizeof(name), "/truth/silhouettes/%s/%06u.png",
                    cam.calibration.name.c_str(), f);
      StatusOr<Image> sil = ReadImage(dir + name);
      ASSERT_TRUE(sil.ok()) << sil.status().ToString();
      std::vector<uint8_t> rendered(sil->pixels.size());
      size_t area = 0;
      for (size_t i = 0; i < rendered.size(); ++i) area += rendered[i] = sil->pixels[i] > 127;
      EXPECT_GT(area, 300u) << "the actor should be in view of " << cam.calibration.name;
      const std::vector<uint8_t> projected =
          ProjectMesh(cam.calibration, actor.PosedPositions(f), actor.mesh().indices);
      const int w = int(cam.calibration.width), h = int(cam.calibration.height);
      EXPECT_EQ(DisagreementsBeyondOnePixel(rendered, projected, w, h), 0) << name;
      EXPECT_EQ(DisagreementsBeyondOnePixel(projected, rendered, w, h), 0) << name;
    }
  }
}

TEST_F(SynthTest, SilhouettesMatchTheProjectedMeshWithinAPixel) {
  ASSERT_TRUE(result_.ok()) << result_.ToString();
  StatusOr<std::unique_ptr<Actor>> actor = MakeSynthActor(options_);
  ASSERT_TRUE(actor.ok());
  ExpectSilhouettesMatchMesh(dir_, **actor, {0, 3});
}

// A body that is not our model: CesiumMan (19 joints) from ../shared/data.
TEST(SynthGltf, CesiumManCaptureMatchesItsMesh) {
  const char* env = std::getenv("FVV_TEST_DATA");
  const std::string model = std::string(env ? env : FVV_TEST_DATA_DIR) + "/models/CesiumMan.glb";
  std::ifstream probe(model);
  if (!probe) GTEST_SKIP() << model << " absent (third-party data)";
  SynthOptions o;
  o.output_dir = ::testing::TempDir() + "/synth_cesium_" + std::to_string(getpid());
  std::system(("rm -rf '" + o.output_dir + "'").c_str());
  o.actor = model;
  o.cameras = 2;
  o.width = 160;
  o.height = 120;
  o.frames = 3;
  o.held_out = 0;
  StatusOr<SynthSummary> r = RunSynth(o);
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  StatusOr<std::unique_ptr<Actor>> actor = MakeSynthActor(o);
  ASSERT_TRUE(actor.ok());
  EXPECT_EQ((*actor)->bone_count(), 19u);
  ExpectSilhouettesMatchMesh(o.output_dir, **actor, {0, 2});
  std::ifstream in(o.output_dir + "/truth/truth.json");
  const nlohmann::json truth = nlohmann::json::parse(in);
  EXPECT_EQ(truth["frames"][0]["joints"].size(), 19u);
  EXPECT_FALSE(truth["frames"][0].contains("dofs"));
}

TEST_F(SynthTest, TruthJointsArePosedBodyJoints) {
  ASSERT_TRUE(result_.ok()) << result_.ToString();
  std::ifstream in(dir_ + "/truth/truth.json");
  const nlohmann::json truth = nlohmann::json::parse(in);
  StatusOr<std::unique_ptr<Actor>> actor = MakeSynthActor(options_);
  ASSERT_TRUE(actor.ok());
  const auto* body = dynamic_cast<const BodyModelActor*>(actor->get());
  ASSERT_NE(body, nullptr);
  for (uint32_t f = 0; f < 4; ++f) {
    const std::vector<double> dofs = truth["frames"][f]["dofs"].get<std::vector<double>>();
    const std::vector<Eigen::Vector3d> joints = JointPositions(body->model().skeleton, dofs);
    for (size_t j = 0; j < joints.size(); ++j) {
      const auto& p = truth["frames"][f]["joints"][body->model().skeleton.bones[j].name];
      EXPECT_NEAR(p[0].get<double>(), joints[j].x(), 1e-9);
      EXPECT_NEAR(p[1].get<double>(), joints[j].y(), 1e-9);
      EXPECT_NEAR(p[2].get<double>(), joints[j].z(), 1e-9);
    }
  }
  // The motion moves: the root travels between the first and last frame.
  const auto& a = truth["frames"][0]["joints"]["root"];
  const auto& b = truth["frames"][3]["joints"]["root"];
  EXPECT_GT(
      std::hypot(a[0].get<double>() - b[0].get<double>(), a[2].get<double>() - b[2].get<double>()),
      0.02);
}

// Frames differ from the background plate inside the silhouette (the actor)
// and barely outside it (noise, the soft shadow near the feet).
TEST_F(SynthTest, FramesDifferFromPlatesWhereTheActorIs) {
  ASSERT_TRUE(result_.ok()) << result_.ToString();
  StatusOr<Capture> c = LoadCapture(dir_);
  ASSERT_TRUE(c.ok());
  CaptureReader reader(*c);
  StatusOr<Image> frame = reader.ReadFrame(0, 1), plate = reader.ReadBackground(0);
  ASSERT_TRUE(frame.ok() && plate.ok());
  StatusOr<Image> sil = ReadImage(dir_ + "/truth/silhouettes/cam00/000001.png");
  ASSERT_TRUE(sil.ok());
  double inside = 0, outside = 0;
  size_t n_in = 0, n_out = 0;
  for (size_t i = 0; i < sil->pixels.size(); ++i) {
    double d = 0;
    for (int k = 0; k < 3; ++k)
      d += std::abs(int(frame->pixels[3 * i + k]) - int(plate->pixels[3 * i + k]));
    if (sil->pixels[i])
      inside += d, ++n_in;
    else
      outside += d, ++n_out;
  }
  EXPECT_GT(inside / n_in, 40.0);
  EXPECT_LT(outside / n_out, 8.0);  // noise (sigma 2 per channel, two images) and shadow
}

TEST_F(SynthTest, DeterministicForASeed) {
  ASSERT_TRUE(result_.ok()) << result_.ToString();
  SynthOptions again = options_;
  again.output_dir = dir_ + "_again";
  again.frames = 2;
  again.held_out = 0;
  std::system(("rm -rf '" + again.output_dir + "'").c_str());
  ASSERT_TRUE(RunSynth(again).ok());
  SynthOptions other = again;
  other.output_dir = dir_ + "_other";
  other.seed = 6;
  std::system(("rm -rf '" + other.output_dir + "'").c_str());
  ASSERT_TRUE(RunSynth(other).ok());
  StatusOr<Image> a = ReadImage(dir_ + "/cam01/000001.png");
  StatusOr<Image> b = ReadImage(again.output_dir + "/cam01/000001.png");
  StatusOr<Image> o = ReadImage(other.output_dir + "/cam01/000001.png");
  ASSERT_TRUE(a.ok() && b.ok() && o.ok());
  EXPECT_EQ(a->pixels, b->pixels);
  EXPECT_NE(a->pixels, o->pixels);
}

// The conditions of a real take, against the same take without them (same
// seed, so the actor and the noise are the same): no plates written or listed;
// the clutter changes the studio's pixels but not the actor's; the bystander
// changes pixels outside the actor's silhouette, never the truth (silhouettes,
// joints); truth.json records the conditions.
TEST_F(SynthTest, RealTakeConditionsChangeTheFramesNotTheTruth) {
  ASSERT_TRUE(result_.ok()) << result_.ToString();
  SynthOptions clean = options_;
  clean.output_dir = dir_ + "_clean";
  clean.frames = 2;
  clean.held_out = 0;
  clean.cameras = 4;
  SynthOptions real = clean;
  real.output_dir = dir_ + "_real";
  real.plates = false, real.clutter = true, real.bystander = true;
  std::system(("rm -rf '" + clean.output_dir + "' '" + real.output_dir + "'").c_str());
  ASSERT_TRUE(RunSynth(clean).ok());
  StatusOr<SynthSummary> made = RunSynth(real);
  ASSERT_TRUE(made.ok()) << made.status().ToString();
  StatusOr<Capture> c = LoadCapture(real.output_dir);
  ASSERT_TRUE(c.ok()) << c.status().ToString();
  CaptureReader reader(*c);
  EXPECT_FALSE(reader.HasBackgrounds());
  struct stat st;
  EXPECT_NE(stat((real.output_dir + "/background").c_str(), &st), 0);
  std::ifstream truth_file(real.output_dir + "/truth/truth.json");
  const nlohmann::json truth = nlohmann::json::parse(truth_file);
  EXPECT_EQ(truth["plates"], false);
  EXPECT_EQ(truth["clutter"], true);
  EXPECT_EQ(truth["bystander"], true);
  std::ifstream clean_truth_file(clean.output_dir + "/truth/truth.json");
  const nlohmann::json clean_truth = nlohmann::json::parse(clean_truth_file);
  EXPECT_EQ(truth["frames"], clean_truth["frames"]);
  size_t changed_outside = 0, changed_inside = 0, outside = 0;
  for (const char* cam : {"cam00", "cam01", "cam02", "cam03"}) {
    const std::string name = std::string(cam) + "/000001.png";
    StatusOr<Image> a = ReadImage(clean.output_dir + "/" + name);
    StatusOr<Image> b = ReadImage(real.output_dir + "/" + name);
    StatusOr<Image> sa = ReadImage(clean.output_dir + "/truth/silhouettes/" + name);
    StatusOr<Image> sb = ReadImage(real.output_dir + "/truth/silhouettes/" + name);
    ASSERT_TRUE(a.ok() && b.ok() && sa.ok() && sb.ok());
    EXPECT_EQ(sa->pixels, sb->pixels) << cam;
    for (size_t i = 0; i < sa->pixels.size(); ++i) {
      int d = 0;
      for (int k = 0; k < 3; ++k)
        d += std::abs(int(a->pixels[3 * i + k]) - int(b->pixels[3 * i + k]));
      if (sa->pixels[i]) {
        changed_inside += d > 30;
      } else {
        ++outside;
        changed_outside += d > 30;
      }
    }
  }
  // Props and the bystander cover part of the studio; the actor stays itself
  // except where the bystander passes in front of it.
  EXPECT_GT(changed_outside, outside / 50) << changed_outside << " of " << outside;
  EXPECT_LT(changed_inside, changed_outside);
  std::system(("rm -rf '" + clean.output_dir + "' '" + real.output_dir + "'").c_str());
}

// Background subtraction against the plates recovers the true silhouettes,
// shadows excluded: what tracking starts from.
TEST_F(SynthTest, BackgroundSubtractionRecoversSilhouettes) {
  ASSERT_TRUE(result_.ok()) << result_.ToString();
  StatusOr<Capture> c = LoadCapture(dir_);
  ASSERT_TRUE(c.ok());
  CaptureReader reader(*c);
  for (uint32_t cam = 0; cam < c->cameras.size(); ++cam) {
    StatusOr<Image> plate = reader.ReadBackground(cam);
    ASSERT_TRUE(plate.ok());
    BackgroundModel bg{*plate};
    for (uint32_t f : {0u, 2u}) {
      StatusOr<Image> frame = reader.ReadFrame(cam, f);
      ASSERT_TRUE(frame.ok());
      StatusOr<Image> sil = ExtractSilhouette(*frame, bg);
      ASSERT_TRUE(sil.ok()) << sil.status().ToString();
      char name[128];
      std::snprintf(name, sizeof(name), "/truth/silhouettes/cam%02u/%06u.png", cam, f);
      StatusOr<Image> truth = ReadImage(dir_ + name);
      ASSERT_TRUE(truth.ok());
      const double iou = MaskIou(*sil, *truth);
      std::printf("  camera %u frame %u: silhouette IoU %.3f\n", cam, f, iou);
      EXPECT_GT(iou, 0.93) << name;
    }
  }
}

TEST(Silhouette, EmptyFrameGivesEmptyMaskAndSizesMustMatch) {
  Image plate;
  plate.width = 40, plate.height = 30;
  plate.pixels.assign(40 * 30 * 3, 90);
  StatusOr<Image> empty = ExtractSilhouette(plate, BackgroundModel{plate});
  ASSERT_TRUE(empty.ok());
  for (uint8_t p : empty->pixels) ASSERT_EQ(p, 0);
  Image frame = plate;
  for (int y = 5; y < 25; ++y) {
    for (int x = 10; x < 20; ++x) {
      for (int k = 0; k < 3; ++k) frame.pixels[(y * 40 + x) * 3 + k] = k == 0 ? 200 : 40;
    }
  }
  for (int x = 25; x < 35; ++x) {  // a shadow: darker, same chroma
    for (int k = 0; k < 3; ++k) frame.pixels[(20 * 40 + x) * 3 + k] = 60;
  }
  StatusOr<Image> sil = ExtractSilhouette(frame, BackgroundModel{plate});
  ASSERT_TRUE(sil.ok());
  EXPECT_EQ(sil->pixels[15 * 40 + 15], 255);
  EXPECT_EQ(sil->pixels[20 * 40 + 30], 0);  // the shadow stays background
  Image small = plate;
  small.width = 20;
  small.pixels.resize(20 * 30 * 3);
  EXPECT_FALSE(ExtractSilhouette(small, BackgroundModel{plate}).ok());
}

TEST(Synth, RejectsBadOptions) {
  SynthOptions o;
  o.output_dir = ::testing::TempDir() + "/synth_bad_" + std::to_string(getpid());
  o.cameras = 0;
  EXPECT_FALSE(RunSynth(o).ok());
  o.cameras = 2;
  o.actor = "/nonexistent/character.glb";
  StatusOr<SynthSummary> r = RunSynth(o);
  ASSERT_FALSE(r.ok());
  o.actor = "builtin";
  o.motion = "/nonexistent/motion.bvh";
  EXPECT_FALSE(RunSynth(o).ok());
  o.motion.clear();
  o.output_dir.clear();
  EXPECT_FALSE(RunSynth(o).ok());
}

}  // namespace
}  // namespace fvv
