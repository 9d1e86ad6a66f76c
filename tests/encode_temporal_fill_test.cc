// A texel no camera saw in a frame takes the colour of the nearest frames of
// its span that saw it (encoder/encode/temporal_fill.h).
#include <gtest/gtest.h>

#include <vector>

#include "encoder/encode/temporal_fill.h"

namespace fvv {
namespace {

// One texel (index 1 of 2) over a span of frames, 2 cameras; camera 1 is the
// fallback's target.
struct Span {
  explicit Span(uint32_t n)
      : frames(n),
        colour(n, std::vector<uint8_t>(2 * 3, 0)),
        labels(n, std::vector<int16_t>(2, -1)),
        target(n, std::vector<int16_t>{1, 1}),
        rgb(size_t(n) * 2 * 2 * 3, 0),
        mask(size_t(n) * 2 * 2, 0) {}
  // Frame t saw the texel as grey level v (camera 0).
  void See(uint32_t t, uint8_t v) {
    for (int k = 0; k < 3; ++k) colour[t][3 + k] = v;
    labels[t][1] = 0;
    mask[(size_t(t) * 2 + 0) * 2 + 1] = 1;
  }
  uint64_t Fill(uint32_t max_distance) {
    return FillFromNearestFrames(frames, 2, 2, {1}, colour, labels, target, max_distance,
                                 rgb.data(), mask.data());
  }
  // What the fallback camera's texture holds at frame t, or -1 if unfilled.
  int Filled(uint32_t t) const {
    const size_t i = (size_t(t) * 2 + 1) * 2 + 1;
    return mask[i] ? rgb[i * 3] : -1;
  }
  uint32_t frames;
  std::vector<std::vector<uint8_t>> colour;
  std::vector<std::vector<int16_t>> labels, target;
  std::vector<uint8_t> rgb, mask;
};

TEST(TemporalFill, TakesTheMeanOfTheFramesWithinReachThatSawIt) {
  Span s(8);
  s.See(0, 10), s.See(1, 20), s.See(6, 200);
  EXPECT_EQ(s.Fill(2), 5u);  // frames 2, 3 (from 0-1) and 4, 5, 7 (from 6)
  EXPECT_EQ(s.Filled(0), -1) << "a frame that saw it is left alone";
  EXPECT_EQ(s.Filled(2), 15);   // frames 0 and 1
  EXPECT_EQ(s.Filled(3), 20);   // frame 1 only: 0 is 3 frames away
  EXPECT_EQ(s.Filled(4), 200);  // frame 6 only
  EXPECT_EQ(s.Filled(5), 200);
  EXPECT_EQ(s.Filled(7), 200);
  // Where the look changed, the fill follows the nearest frames, not the
  // span's mean.
  EXPECT_NE(s.Filled(5), (10 + 20 + 200) / 3);
}

TEST(TemporalFill, LeavesTexelsOutOfReachAndWithoutATargetCamera) {
  Span s(8);
  s.See(0, 50);
  s.target[1][1] = -1;
  EXPECT_EQ(s.Fill(3), 2u);
  EXPECT_EQ(s.Filled(1), -1) << "no camera to write it into";
  EXPECT_EQ(s.Filled(2), 50);
  EXPECT_EQ(s.Filled(3), 50);
  EXPECT_EQ(s.Filled(4), -1) << "4 frames from the one that saw it";
  Span never(4);
  EXPECT_EQ(never.Fill(100), 0u);
}

}  // namespace
}  // namespace fvv
