// The silhouettes tracking read against fvv synth's true ones
// (encoder/track/silhouette_truth.h).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <string>

#include "encoder/io/image_io.h"
#include "encoder/track/silhouette_truth.h"

namespace fvv {
namespace {

// A 10x10 mask whose columns [x0, x1) are set.
Image Columns(int x0, int x1) {
  Image m;
  m.width = m.height = 10;
  m.channels = 1;
  m.pixels.assign(100, 0);
  for (int y = 0; y < 10; ++y) {
    for (int x = x0; x < x1; ++x) m.pixels[size_t(y) * 10 + x] = 255;
  }
  return m;
}

class SilhouetteTruthTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = ::testing::TempDir() + "/silhouette_truth_" + std::to_string(getpid());
    std::system(("rm -rf '" + dir_ + "' && mkdir -p '" + dir_ + "/truth/silhouettes/cam00' '" +
                 dir_ + "/truth/silhouettes/cam01' '" + dir_ + "/saved'")
                    .c_str());
    // cam00: the same in frame 0, half in frame 1; cam01: disjoint.
    ASSERT_TRUE(WritePng(dir_ + "/truth/silhouettes/cam00/000000.png", Columns(0, 4)).ok());
    ASSERT_TRUE(WritePng(dir_ + "/saved/cam00_000000.png", Columns(0, 4)).ok());
    ASSERT_TRUE(WritePng(dir_ + "/truth/silhouettes/cam00/000001.png", Columns(0, 4)).ok());
    ASSERT_TRUE(WritePng(dir_ + "/saved/cam00_000001.png", Columns(0, 2)).ok());
    for (const char* f : {"000000", "000001"}) {
      ASSERT_TRUE(WritePng(dir_ + "/truth/silhouettes/cam01/" + f + ".png", Columns(0, 3)).ok());
      ASSERT_TRUE(WritePng(dir_ + "/saved/cam01_" + f + ".png", Columns(5, 9)).ok());
    }
  }
  void TearDown() override { std::system(("rm -rf '" + dir_ + "'").c_str()); }
  std::string dir_;
};

TEST_F(SilhouetteTruthTest, IoUPerCameraAndOverAll) {
  StatusOr<SilhouetteAgreement> a =
      CompareSilhouettesWithTruth(dir_, dir_ + "/saved", {"cam00", "cam01"}, 0, 1);
  ASSERT_TRUE(a.ok()) << a.status().ToString();
  EXPECT_EQ(a->frames, 2u);
  ASSERT_EQ(a->iou.size(), 2u);
  EXPECT_DOUBLE_EQ(a->iou[0], (1.0 + 0.5) / 2);
  EXPECT_DOUBLE_EQ(a->iou[1], 0.0);
  EXPECT_DOUBLE_EQ(a->mean, 0.375);
  // The truth/ directory itself is taken too.
  EXPECT_TRUE(CompareSilhouettesWithTruth(dir_ + "/truth", dir_ + "/saved", {"cam00"}, 0, 0).ok());
}

TEST_F(SilhouetteTruthTest, AMissingOrMisfitFileIsNamed) {
  StatusOr<SilhouetteAgreement> a =
      CompareSilhouettesWithTruth(dir_, dir_ + "/saved", {"cam00"}, 0, 2);
  ASSERT_FALSE(a.ok());
  EXPECT_NE(a.status().message().find("000002.png"), std::string::npos) << a.status().message();
  Image small = Columns(0, 4);
  small.width = 5, small.height = 20;
  ASSERT_TRUE(WritePng(dir_ + "/saved/cam00_000000.png", small).ok());
  a = CompareSilhouettesWithTruth(dir_, dir_ + "/saved", {"cam00"}, 0, 0);
  ASSERT_FALSE(a.ok());
  EXPECT_NE(a.status().message().find("cam00_000000.png"), std::string::npos)
      << a.status().message();
  EXPECT_FALSE(CompareSilhouettesWithTruth(dir_ + "/saved", dir_ + "/saved", {"cam00"}, 0, 0).ok())
      << "no true silhouettes there";
}

}  // namespace
}  // namespace fvv
