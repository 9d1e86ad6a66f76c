// The player's quality control against a simulated decoder whose time is a
// fixed part plus SPIHT work cut at the budget.
#include <gtest/gtest.h>

#include <algorithm>

#include "player/playback/playback_controller.h"

namespace fvv {
namespace {

struct SimDecoder {
  double fixed_ms, spiht_ms;
  // (decode ms, complete)
  std::pair<double, bool> Decode(double max_ms) const {
    if (max_ms <= 0 || max_ms >= spiht_ms) return {fixed_ms + spiht_ms, true};
    return {fixed_ms + max_ms, false};
  }
};

TEST(PlaybackController, CutsDecodingToKeepUpAndRestoresQuality) {
  // 25 fps, 8-frame GOPs: 320 ms of play per GOP, minus 8 frames x 4 ms
  // rendering, 80% of that for decoding: 230.4 ms.
  PlaybackController pc(25, 8, 0.8);
  const double render_ms = 4;
  SimDecoder slow{120, 300};  // a full decode takes 420 ms: too slow
  double decode = 0;
  for (int gop = 0; gop < 12; ++gop) {
    const auto r = slow.Decode(pc.NextMaxMs());
    decode = r.first;
    pc.Report(r.first, render_ms, r.second);
  }
  EXPECT_NEAR(pc.target_ms(), 230.4, 1e-9);
  EXPECT_LE(decode, pc.target_ms());        // keeps up
  EXPECT_GT(decode, 0.6 * pc.target_ms());  // without wasting the budget
  EXPECT_GT(pc.NextMaxMs(), 0.0);
  // Decoding gets cheap (smaller GOPs, a faster machine): back to full quality.
  SimDecoder fast{20, 60};
  for (int gop = 0; gop < 20 && pc.NextMaxMs() != 0; ++gop) {
    const auto r = fast.Decode(pc.NextMaxMs());
    pc.Report(r.first, render_ms, r.second);
  }
  EXPECT_EQ(pc.NextMaxMs(), 0.0);
}

// When the fixed part alone misses the target (a slow machine, a software GL
// renderer sharing the cores), cutting the streams cannot help: the budget
// stops at its floor instead of decoding nothing.
TEST(PlaybackController, NeverCutsBelowTheFloorWhenFixedCostsMissTheTarget) {
  PlaybackController pc(25, 8, 0.8);
  SimDecoder heavy{300, 150};  // the fixed 300 ms alone exceed the 230 ms target
  for (int gop = 0; gop < 30; ++gop) {
    const auto r = heavy.Decode(pc.NextMaxMs());
    pc.Report(r.first, 4, r.second);
  }
  EXPECT_NEAR(pc.NextMaxMs(), PlaybackController::kFloorShare * pc.target_ms(), 1e-9);
}

TEST(PlaybackController, FasterPlaybackTightensTheBudget) {
  PlaybackController pc(25, 8, 0.8);
  pc.set_speed(2.0);
  pc.Report(200, 2, true);  // 200 ms > (160 - 16) ms * 0.8 at double speed
  EXPECT_GT(pc.NextMaxMs(), 0.0);
  EXPECT_NEAR(pc.target_ms(), 115.2, 1e-9);
}

}  // namespace
}  // namespace fvv
