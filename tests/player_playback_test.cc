// The player's quality control against a simulated decoder whose time is a
// fixed part plus SPIHT work cut at the budget, above a floor it cannot cut,
// and a simulated playhead that waits when a GOP is later than its play time.
#include <gtest/gtest.h>

#include <algorithm>

#include "player/playback/fetch_plan.h"
#include "player/playback/playback_controller.h"

namespace fvv {
namespace {

constexpr double kGopMs = 320;  // 8 frames at 25 fps

struct SimDecoder {
  double fixed_ms, spiht_ms;
  double floor_share = 0.1;
  double slowdown = 1;  // another process on the cores: everything takes longer
  // A GOP decoded under max_ms, as the player reports it (with the wait its
  // lateness cost the playhead).
  GopOutcome Decode(double max_ms, double play_ms = kGopMs) const {
    GopOutcome g;
    g.budget_ms = max_ms;
    g.frame_ms = 5;
    const double spiht = spiht_ms * slowdown, floor_ms = floor_share * spiht;
    if (max_ms <= 0 || max_ms >= spiht) {
      g.decode_ms = fixed_ms * slowdown + spiht;
      g.complete = true;
    } else {
      g.decode_ms = fixed_ms * slowdown + std::max(max_ms, floor_ms);
      g.complete = false;
    }
    g.wait_ms = std::max(0.0, g.decode_ms - play_ms);
    return g;
  }
  // The share of the streams' bytes decoded under max_ms.
  double Share(double max_ms) const {
    const double spiht = spiht_ms * slowdown;
    if (max_ms <= 0 || max_ms >= spiht) return 1;
    return std::max(floor_share, max_ms / spiht);
  }
};

TEST(PlaybackController, CutsDecodingToKeepUpAndRestoresQuality) {
  PlaybackController pc(25, 8);
  SimDecoder slow{120, 300};  // a full decode takes 420 ms of a GOP's 320
  GopOutcome g;
  for (int gop = 0; gop < 12; ++gop) {
    g = slow.Decode(pc.NextMaxMs());
    pc.Report(g);
  }
  EXPECT_EQ(g.wait_ms, 0);               // keeps up
  EXPECT_GT(g.decode_ms, 0.8 * kGopMs);  // without wasting the time it has
  EXPECT_GT(pc.NextMaxMs(), 0.0);
  EXPECT_FALSE(pc.below_real_time());
  // Decoding gets cheap (the load went, a faster machine): a whole decode
  // again within two GOPs.
  SimDecoder fast{20, 60};
  for (int gop = 0; gop < 2; ++gop) pc.Report(fast.Decode(pc.NextMaxMs()));
  EXPECT_TRUE(fast.Decode(pc.NextMaxMs()).complete);
}

// A load that makes even the fixed part slower than the play time: the budget
// goes to its minimum, the floor's bytes are still decoded, and the controller
// says playback is below real time.
TEST(PlaybackController, KeepsTheFloorAndSaysSoWhenEvenItIsTooSlow) {
  PlaybackController pc(25, 8, 0.1);
  EXPECT_EQ(pc.floor_share(), 0.1);
  SimDecoder heavy{360, 150};  // the fixed 360 ms alone exceed the 320 ms of play
  double share = 1;
  for (int gop = 0; gop < 30; ++gop) {
    share = heavy.Share(pc.NextMaxMs());
    pc.Report(heavy.Decode(pc.NextMaxMs()));
  }
  EXPECT_GE(share, 0.1);
  EXPECT_LE(pc.NextMaxMs(), 2.0);
  EXPECT_TRUE(pc.below_real_time());
}

// A load step: the share decoded falls while the cores are busy, never below the
// floor, and is back to 90 % of the idle share within 2 s (6 GOPs) of the
// load's end.
TEST(PlaybackController, RecoversQualitySoonAfterALoadStep) {
  PlaybackController pc(25, 8);
  SimDecoder dec{60, 200};
  double idle = 0, loaded = 1;
  for (int gop = 0; gop < 10; ++gop) {
    idle = dec.Share(pc.NextMaxMs());
    pc.Report(dec.Decode(pc.NextMaxMs()));
  }
  dec.slowdown = 3;
  for (int gop = 0; gop < 20; ++gop) {
    loaded = std::min(loaded, dec.Share(pc.NextMaxMs()));
    pc.Report(dec.Decode(pc.NextMaxMs()));
  }
  EXPECT_LT(loaded, 0.8 * idle);
  EXPECT_GE(loaded, dec.floor_share);
  dec.slowdown = 1;
  int back = -1;
  for (int gop = 0; gop < 12 && back < 0; ++gop) {
    if (dec.Share(pc.NextMaxMs()) >= 0.9 * idle) back = gop;
    pc.Report(dec.Decode(pc.NextMaxMs()));
  }
  EXPECT_GE(back, 0);
  EXPECT_LE(back, 6);
}

// The reserve comes from measured waits: a GOP that was late grows it by the
// wait; GOPs in time shrink it back towards two frame times.
TEST(PlaybackController, ReserveFollowsMeasuredWaits) {
  PlaybackController pc(25, 8);
  GopOutcome late;
  late.decode_ms = 400;
  late.wait_ms = 80;
  late.frame_ms = 5;
  pc.Report(late);
  EXPECT_NEAR(pc.reserve_ms(), 80, 1e-9);
  EXPECT_NEAR(pc.target_ms(), kGopMs - 80, 1e-9);
  GopOutcome in_time;
  in_time.decode_ms = 100;
  in_time.frame_ms = 5;
  for (int gop = 0; gop < 20; ++gop) pc.Report(in_time);
  EXPECT_NEAR(pc.reserve_ms(), 5, 1e-9);
  // A wait while the budget is at its smallest came from the floor, which no
  // reserve shortens: the reserve does not grow.
  GopOutcome floor_late;
  floor_late.budget_ms = 1;
  floor_late.complete = false;
  floor_late.decode_ms = 500;
  floor_late.wait_ms = 180;
  floor_late.frame_ms = 5;
  pc.Report(floor_late);
  EXPECT_NEAR(pc.reserve_ms(), 5, 1e-9);
  EXPECT_TRUE(pc.below_real_time());
}

// One cheap GOP under a steady load does not swing the next from the floor to a
// whole decode: the budget rises at most fourfold (and 20 ms) a GOP, and falls
// at once.
TEST(PlaybackController, BudgetRisesInStepsAndFallsAtOnce) {
  PlaybackController pc(25, 8);
  SimDecoder loaded{330, 200};  // the fixed part alone is longer than the GOP plays
  for (int gop = 0; gop < 10; ++gop) pc.Report(loaded.Decode(pc.NextMaxMs()));
  const double at_floor = pc.NextMaxMs();
  EXPECT_LE(at_floor, 2.0);
  SimDecoder idle{40, 150};
  pc.Report(idle.Decode(pc.NextMaxMs()));
  EXPECT_LE(pc.NextMaxMs(), 4 * at_floor + 20 + 1e-9);
  EXPECT_GT(pc.NextMaxMs(), at_floor);
  for (int gop = 0; gop < 3; ++gop) pc.Report(idle.Decode(pc.NextMaxMs()));
  const double recovered = pc.NextMaxMs();
  EXPECT_GE(recovered, 150.0);  // a whole decode again
  pc.Report(loaded.Decode(recovered));
  EXPECT_LT(pc.NextMaxMs(), 0.5 * recovered);
}

// A decoder whose every camera costs its floor (transform, first bitplanes)
// whatever the budget, with more cameras than that fits in a GOP's play: the
// controller limits the cameras to those that fit, and playback keeps real
// time where the budget alone (already at its smallest) could not; when
// decoding gets cheap again the limit goes.
TEST(PlaybackController, LimitsTheCamerasWhenEvenTheirFloorOutlastsTheGop) {
  PlaybackController pc(25, 8);
  EXPECT_EQ(pc.max_cameras(), PlaybackController::kMinCameras)
      << "the closest three before anything was measured";
  const uint32_t wanted = 6;
  double per_camera_ms = 90;  // six cameras' floor: 540 ms of a GOP's 320
  uint32_t cameras = wanted;
  GopOutcome g;
  for (int gop = 0; gop < 8; ++gop) {
    cameras = pc.max_cameras() ? std::min(wanted, pc.max_cameras()) : wanted;
    g = GopOutcome{};
    g.budget_ms = pc.NextMaxMs();
    g.decode_ms = per_camera_ms * cameras + std::min(g.budget_ms, 40.0 * cameras);
    g.complete = g.budget_ms >= 40.0 * cameras;
    g.frame_ms = 5;
    g.cameras = cameras;
    g.wait_ms = std::max(0.0, g.decode_ms - kGopMs);
    pc.Report(g);
  }
  EXPECT_EQ(cameras, PlaybackController::kMinCameras);
  EXPECT_EQ(g.wait_ms, 0) << "three cameras' floor fits";
  EXPECT_FALSE(pc.below_real_time());
  EXPECT_GT(pc.NextMaxMs(), 2.0) << "with room above the floor";
  // Never fewer than the blend's closest three, however slow.
  per_camera_ms = 400;
  for (int gop = 0; gop < 4; ++gop) {
    g.budget_ms = pc.NextMaxMs();
    g.decode_ms = per_camera_ms * cameras + g.budget_ms;
    g.complete = false;
    pc.Report(g);
  }
  EXPECT_EQ(pc.max_cameras(), PlaybackController::kMinCameras);
  // The load goes: whole decodes of three cameras in 60 ms lift the limit.
  for (int gop = 0; gop < 3; ++gop) {
    g.budget_ms = pc.NextMaxMs();
    g.decode_ms = 60;
    g.complete = true;
    g.wait_ms = 0;
    pc.Report(g);
  }
  EXPECT_TRUE(pc.max_cameras() == 0 || pc.max_cameras() >= wanted) << pc.max_cameras();
}

// The first GOPs decode before anything is measured, while the first frames
// are drawn, and the start waits for them: the blend's closest three. The
// first outcome sets the limit: none after a whole decode in time.
TEST(PlaybackController, TheStartDecodesTheClosestThreeUntilAGopIsMeasured) {
  PlaybackController pc(25, 8);
  EXPECT_EQ(pc.max_cameras(), PlaybackController::kMinCameras);
  GopOutcome g;
  g.budget_ms = pc.NextMaxMs();
  g.decode_ms = 40;
  g.complete = true;
  g.cameras = 3;
  pc.Report(g);
  EXPECT_EQ(pc.max_cameras(), 0u) << "a whole decode in time: no limit";
  PlaybackController slow(25, 8);
  g.decode_ms = g.budget_ms + 3 * 150;  // 150 ms a camera that no budget shortens
  g.complete = false;
  slow.Report(g);
  EXPECT_EQ(slow.max_cameras(), PlaybackController::kMinCameras);
}

TEST(PlaybackController, FasterPlaybackTightensTheBudget) {
  PlaybackController pc(25, 8);
  pc.set_speed(2.0);
  GopOutcome g;
  g.budget_ms = 100;
  g.complete = false;
  g.decode_ms = 200;  // 100 ms beyond its budget: the fixed part
  g.frame_ms = 2;
  pc.Report(g);
  EXPECT_NEAR(pc.target_ms(), 160 - 2, 1e-9);
  EXPECT_NEAR(pc.fixed_ms(), 100, 1e-9);
  EXPECT_NEAR(pc.NextMaxMs(), 58, 1e-9);
}

}  // namespace
}  // namespace fvv

namespace fvv {
namespace {

// A GOP fetched over HTTP: every fragment its head, then the same share of
// every fragment's texture, never more than the bandwidth's budget in all.
TEST(FetchPlan, HeadsFirstThenTheSameShareOfEveryTextureWithinTheBudget) {
  const std::vector<FragmentSizes> gop = {{300, 20300}, {99, 10099}, {99, 5099}};
  // Whole fragments when the budget holds them.
  EXPECT_EQ(PlanPrefixes(gop, 40000), (std::vector<uint64_t>{20300, 10099, 5099}));
  // Heads only when even they exceed it (the caller waits for them).
  EXPECT_EQ(PlanPrefixes(gop, 300), (std::vector<uint64_t>{300, 99, 99}));
  // In between: 7000 bytes past the heads, of 35000 texture bytes, is a fifth of each.
  const std::vector<uint64_t> p = PlanPrefixes(gop, 498 + 7000);
  EXPECT_EQ(p, (std::vector<uint64_t>{300 + 4000, 99 + 2000, 99 + 1000}));
  for (uint64_t budget = 0; budget < 40000; budget += 777) {
    const std::vector<uint64_t> q = PlanPrefixes(gop, budget);
    uint64_t sum = 0;
    for (size_t i = 0; i < q.size(); ++i) {
      EXPECT_GE(q[i], gop[i].head);
      EXPECT_LE(q[i], gop[i].size);
      sum += q[i];
    }
    EXPECT_LE(sum, std::max<uint64_t>(budget, 498)) << budget;
    EXPECT_GE(sum + 3, std::min<uint64_t>(std::max<uint64_t>(budget, 498), 35498)) << budget;
  }
  EXPECT_TRUE(PlanPrefixes({}, 1000).empty());
}

// Camera group 0's fragment with the surface of every frame: its surface
// comes whole right past its head, before any texture share, or not at all
// (then that fragment stops at its head: bytes into a surface that cannot be
// whole are wasted, and its texture lies past it).
TEST(FetchPlan, TheSurfaceWholeAfterTheHeadsOrThatFragmentStopsAtItsHead) {
  const std::vector<FragmentSizes> gop = {{300, 25300, 5000}, {99, 10099, 0}, {99, 5099, 0}};
  EXPECT_EQ(PlanPrefixes(gop, 50000), (std::vector<uint64_t>{25300, 10099, 5099}));
  // The heads and the surface, then a fifth of each texture (35000 bytes).
  EXPECT_EQ(PlanPrefixes(gop, 498 + 5000 + 7000),
            (std::vector<uint64_t>{300 + 5000 + 4000, 99 + 2000, 99 + 1000}));
  // Room for the heads and less than the surface: it is left out, and the
  // budget goes to the other fragments' textures (15000 bytes, 4000 of them).
  const std::vector<uint64_t> p = PlanPrefixes(gop, 498 + 4000);
  EXPECT_EQ(p[0], 300u);
  EXPECT_EQ(p[1] + p[2], 198u + 4000u - 1u) << p[1] << " " << p[2];
  for (uint64_t budget = 0; budget < 50000; budget += 613) {
    const std::vector<uint64_t> q = PlanPrefixes(gop, budget);
    uint64_t sum = 0;
    for (size_t i = 0; i < q.size(); ++i) sum += q[i];
    EXPECT_LE(sum, std::max<uint64_t>(budget, 498)) << budget;
    // Group 0 stops at its head or holds its whole surface, never between.
    EXPECT_TRUE(q[0] == 300 || q[0] >= 5300) << budget << ": " << q[0];
  }
  // A surface larger than what is left of its fragment counts as that.
  EXPECT_EQ(PlanPrefixes({{300, 1300, 5000}}, 2000), (std::vector<uint64_t>{1300}));
}

TEST(FetchPlan, TheBandwidthFollowsTheFetchesAndSetsTheBudget) {
  BandwidthEstimate b;
  EXPECT_EQ(b.bytes_per_second(), 0);
  b.Measured(62500, 1.0);  // 0.5 Mbit/s
  EXPECT_DOUBLE_EQ(b.bytes_per_second(), 62500);
  b.Measured(125000, 1.0);  // the network doubles: the estimate moves 30 % of the way
  EXPECT_DOUBLE_EQ(b.bytes_per_second(), 62500 * 0.7 + 125000 * 0.3);
  b.Measured(1000, 0);  // no time: ignored
  EXPECT_DOUBLE_EQ(b.bytes_per_second(), 62500 * 0.7 + 125000 * 0.3);
  // Two overlapping fetches at 62.5 KB/s: the second ends 0.05 s after the
  // first, with 20 KB; its own rate (400 KB/s) is no measure of the link.
  BandwidthEstimate overlap;
  overlap.Measured(20000, 0.32);
  overlap.Measured(20000, 0.05);
  overlap.Measured(20000, 0.59);
  EXPECT_NEAR(overlap.bytes_per_second(), 62500, 0.15 * 62500);
  EXPECT_DOUBLE_EQ(BandwidthEstimate(62500).bytes_per_second(), 62500) << "a rate to go on from";
  // 0.5 Mbit/s over an 8-frame GOP at 25 fps: 90 % of 20000 bytes.
  EXPECT_EQ(GopFetchBudget(62500, 8 / 25.0), 18000u);
  EXPECT_EQ(GopFetchBudget(0, 0.32), 0u);
}

}  // namespace
}  // namespace fvv
