// The playback loop over GOPs fetched and decoded outside it (the web
// player's arrangement, player/playback/requested_gops.h): what it asks for,
// in what order, with how many bytes; that it waits rather than skips; that a
// seek survives the wait for its GOP.
#include "player/playback/playback_loop.h"

#include <gtest/gtest.h>

#include <bitset>
#include <cmath>
#include <vector>

#include "player/playback/requested_gops.h"

namespace fvv {
namespace {

constexpr double kFps = 25;
constexpr uint32_t kGopFrames = 8, kFrames = 40;  // 5 GOPs

fvv_stream_info Info() {
  fvv_stream_info info{};
  info.frame_count = kFrames;
  info.frame_rate_num = 25;
  info.frame_rate_den = 1;
  info.camera_count = 4;
  info.gop_frames = kGopFrames;
  info.gop_cameras = 1;
  return info;
}

std::vector<glm::vec3> Ring() { return {{2, 1, 0}, {0, 1, 2}, {-2, 1, 0}, {0, 1, -2}}; }

fvv_decode_report Whole() {
  fvv_decode_report r{};
  r.bytes_decoded = r.bytes_available = 1000;
  r.complete = 1;
  r.decode_ms = 10;
  return r;
}

struct Rig {
  RequestedGops gops{kFrames, kGopFrames};  // fetching as far ahead as decoding
  PlaybackLoop loop{&gops, Info(), Ring()};
  glm::vec3 eye{0, 1, 3}, target{0, 1, 0};
  Status Tick(double dt = 1 / kFps) { return loop.Advance(dt, eye, target); }
  // Fetches the next request at once and decodes what is due; returns the
  // GOP fetched (or -1).
  int Serve() {
    uint32_t gop, decoded;
    GopRequest r;
    if (!gops.NextRequest(&gop, &r)) return -1;
    gops.Fetched(gop);
    while (gops.NextDecode(&decoded, &r)) gops.Deliver(decoded, Whole());
    return int(gop);
  }
};

TEST(PlaybackLoopOverRequests, WaitsForTheFirstGopThenFetchesAhead) {
  Rig rig;
  ASSERT_TRUE(rig.Tick().ok());
  EXPECT_FALSE(rig.loop.has_frame());
  uint32_t gop = 99;
  GopRequest request;
  ASSERT_TRUE(rig.gops.NextRequest(&gop, &request));
  EXPECT_EQ(gop, 0u);
  EXPECT_EQ(request.fetch_bytes, 0u) << "nothing measured yet: whole fragments";
  // The view at +z needs the cameras facing it, not the one behind the actor.
  EXPECT_TRUE(request.budget.camera_mask & (1u << 1));
  EXPECT_FALSE(request.budget.camera_mask & (1u << 3));
  uint32_t other;
  EXPECT_FALSE(rig.gops.NextRequest(&other, &request))
      << "the GOP the playhead waits for has the link to itself";
  for (int i = 0; i < 10; ++i) ASSERT_TRUE(rig.Tick().ok());
  EXPECT_FALSE(rig.loop.has_frame());
  EXPECT_EQ(rig.loop.stats().waits, 0u) << "the wait for the first frame is the start-up";
  rig.gops.Deliver(0, Whole());
  ASSERT_TRUE(rig.Tick().ok());
  ASSERT_TRUE(rig.loop.has_frame());
  EXPECT_EQ(rig.loop.frame_index(), 0u) << "the playhead waited at the first frame";
  EXPECT_EQ(rig.Serve(), 1);
  EXPECT_EQ(rig.Serve(), 2);
  EXPECT_EQ(rig.Serve(), -1) << "at most RequestedGops::kAhead GOPs past the one shown";
}

TEST(PlaybackLoopOverRequests, FetchBytesFollowTheMeasuredBandwidth) {
  Rig rig;
  ASSERT_TRUE(rig.Tick().ok());
  EXPECT_EQ(rig.loop.FetchBudget(), 0u) << "nothing measured: whole fragments";
  rig.loop.FetchMeasured(62500, 1.0);  // 0.5 Mbit/s; a GOP plays 0.32 s
  const double allowed = 62500 * 0.32;
  const uint64_t start = rig.loop.FetchBudget();
  EXPECT_GT(start, 0.5 * allowed) << "a lower share at the start, to get ahead";
  EXPECT_LT(start, 0.7 * allowed);
  // GOPs in time: the share rises to 97 % of what the bandwidth brings, and
  // on with the fetch window full (these fetches finish at once: the next test).
  for (int i = 0; i < 8 * 4; ++i) {
    while (rig.Serve() >= 0) {
    }
    ASSERT_TRUE(rig.Tick().ok());
  }
  const uint64_t steady = rig.loop.FetchBudget();
  EXPECT_GE(steady, 0.97 * allowed);
  EXPECT_LE(steady, 1.2 * allowed);
  rig.loop.FetchMeasured(625000, 1.0);
  EXPECT_GT(rig.loop.FetchBudget(), 2 * steady) << "a faster network, more bytes";
  EXPECT_EQ(rig.loop.stats().bytes_fetched, 62500u + 625000u);
}

// The measured rate undercounts the link (each request pays a round trip):
// with the fetch window full a GOP takes more than it, and 97 % once the
// window is half empty.
TEST(PlaybackLoopOverRequests, TheShareGoesPastTheMeasuredRateAsTheFetchWindowFills) {
  RequestedGops gops(kFrames, kGopFrames, /*fetch_ahead=*/4);
  PlaybackLoop loop(&gops, Info(), Ring());
  const glm::vec3 eye{0, 1, 3}, target{0, 1, 0};
  // Fetches the next request at once (false: none), and decodes what is due.
  auto serve = [&gops] {
    uint32_t gop, decoded;
    GopRequest r;
    const bool fetched = gops.NextRequest(&gop, &r);
    if (fetched) gops.Fetched(gop);
    while (gops.NextDecode(&decoded, &r)) gops.Deliver(decoded, Whole());
    return fetched;
  };
  ASSERT_TRUE(loop.Advance(0.04, eye, target).ok());
  loop.FetchMeasured(62500, 1.0);
  const double allowed = 62500 * 0.32;
  // Every fetch at once: the window is full.
  for (int i = 0; i < 8 * 15; ++i) {
    while (serve()) {
    }
    ASSERT_TRUE(loop.Advance(0.04, eye, target).ok());
  }
  EXPECT_NEAR(loop.FetchBudget(), 1.2 * allowed, 0.01 * allowed) << "up to kMaxFetchShare";
  // Then each GOP just in time, one ahead of four, the others dropped (as
  // the page's cache does): the window is a quarter full.
  uint32_t gop_shown = loop.frame_index() / kGopFrames;
  bool due = false;
  uint64_t budget = 0;  // in the stream's middle (at its end, nothing is left to fetch)
  for (int i = 0; i < 8 * 10; ++i) {
    ASSERT_TRUE(loop.Advance(0.04, eye, target).ok());
    if (gop_shown == 1) budget = loop.FetchBudget();
    if (due) serve();  // the GOP after the one shown, asked for again by now
    due = loop.frame_index() / kGopFrames != gop_shown;
    if (due) {
      gop_shown = loop.frame_index() / kGopFrames;
      for (uint32_t g = 0; g < kFrames / kGopFrames; ++g) {
        if (g != gop_shown) gops.Forget(g);
      }
    }
  }
  EXPECT_EQ(loop.stats().waits, 0u);
  EXPECT_NEAR(budget, 0.97 * allowed, 0.01 * allowed)
      << "back to kSteadyFetchShare, not below: no GOP was late";
}

TEST(PlaybackLoopOverRequests, AQueuedGopIsFetchedWithTheLatestBudget) {
  Rig rig;
  ASSERT_TRUE(rig.Tick().ok());
  rig.Serve();
  ASSERT_TRUE(rig.Tick().ok());  // frame 0 shown: GOPs 1 and 2 asked for, unmeasured
  rig.loop.FetchMeasured(62500, 1.0);
  ASSERT_TRUE(rig.Tick().ok());
  uint32_t gop;
  GopRequest request;
  ASSERT_TRUE(rig.gops.NextRequest(&gop, &request));
  EXPECT_EQ(gop, 1u);
  EXPECT_EQ(request.fetch_bytes, rig.loop.FetchBudget()) << "not the whole fragments first asked";
}

// Eight cameras round the actor, a view 10 degrees off camera 0: four within
// the decode's 90-degree reach. The start asks for the closest three (nothing
// measured yet); GOPs 0 and 1 decode whole in time and the limit lifts, so
// GOP 2 is fetched for the four. Its decode takes 150 ms a camera beyond its
// budget; GOP 3, fetched for four while it decoded and decoded after frame
// 16 was taken, decodes the closest three of them; the GOPs fetched after
// it ask for three.
TEST(PlaybackLoopOverRequests, ADecoderTooSlowForTheViewsCamerasGetsTheClosestThree) {
  fvv_stream_info info = Info();
  info.camera_count = 8;
  std::vector<glm::vec3> ring;
  for (int c = 0; c < 8; ++c) {
    const float a = glm::radians(45.0f * c);
    ring.emplace_back(2 * std::sin(a), 1, 2 * std::cos(a));
  }
  RequestedGops gops{kFrames, kGopFrames};
  PlaybackLoop loop{&gops, info, ring};
  const float a = glm::radians(10.0f);
  const glm::vec3 eye{3 * std::sin(a), 1, 3 * std::cos(a)}, target{0, 1, 0};
  auto count = [](uint64_t mask) { return std::bitset<64>(mask).count(); };
  auto tick = [&] { return loop.Advance(1 / kFps, eye, target).ok(); };
  ASSERT_TRUE(tick());
  uint32_t gop, decoded;
  GopRequest r, d;
  ASSERT_TRUE(gops.NextRequest(&gop, &r));
  ASSERT_EQ(gop, 0u);
  EXPECT_EQ(count(r.budget.camera_mask), 3u) << "the start: the closest three";
  EXPECT_EQ(r.budget.camera_mask & 1u, 1u);
  gops.Fetched(0);
  ASSERT_TRUE(gops.NextDecode(&decoded, &d));
  ASSERT_TRUE(tick());
  ASSERT_TRUE(gops.NextRequest(&gop, &r));
  ASSERT_EQ(gop, 1u);
  EXPECT_EQ(count(r.budget.camera_mask), 3u);
  gops.Fetched(1);
  gops.Deliver(0, Whole());
  ASSERT_TRUE(tick());  // frame 0 shown: GOP 0 was whole in time
  ASSERT_TRUE(loop.has_frame());
  EXPECT_EQ(loop.controller().max_cameras(), 0u);
  ASSERT_TRUE(gops.NextDecode(&decoded, &d));
  ASSERT_EQ(decoded, 1u);
  gops.Deliver(1, Whole());
  // Into GOP 1: the view's cameras, four, for the GOPs asked for from now.
  while (loop.frame_index() < kGopFrames) ASSERT_TRUE(tick());
  ASSERT_TRUE(gops.NextRequest(&gop, &r));
  ASSERT_EQ(gop, 2u);
  const uint64_t four = r.budget.camera_mask;
  ASSERT_EQ(count(four), 4u);
  gops.Fetched(2);
  ASSERT_TRUE(gops.NextDecode(&decoded, &d));
  ASSERT_EQ(decoded, 2u);
  // While GOP 2 decodes, the link fetches GOP 3 for the four.
  ASSERT_TRUE(gops.NextRequest(&gop, &r));
  ASSERT_EQ(gop, 3u);
  EXPECT_EQ(r.budget.camera_mask, four);
  gops.Fetched(3);
  fvv_decode_report slow = Whole();
  slow.complete = 0;
  slow.max_ms_per_gop = d.budget.max_ms_per_gop;
  slow.decode_ms = d.budget.max_ms_per_gop + 150.0 * count(d.budget.camera_mask);
  gops.Deliver(2, slow);  // as many cameras as its decode was asked for
  // The decoder takes GOP 3 only once frame 16 was shown (it was busy).
  while (loop.frame_index() < 2 * kGopFrames) ASSERT_TRUE(tick());  // frame 16 shown
  EXPECT_EQ(loop.controller().max_cameras(), PlaybackController::kMinCameras);
  ASSERT_TRUE(gops.NextDecode(&decoded, &d));
  ASSERT_EQ(decoded, 3u);
  EXPECT_EQ(count(d.budget.camera_mask), 3u);
  EXPECT_EQ(d.budget.camera_mask & ~four, 0u) << "only cameras it was fetched for";
  EXPECT_EQ(d.budget.camera_mask & 1u, 1u) << "camera 0, the closest, is kept";
  ASSERT_TRUE(gops.NextRequest(&gop, &r));
  EXPECT_EQ(gop, 4u);
  EXPECT_EQ(count(r.budget.camera_mask), 3u);
  EXPECT_EQ(r.budget.camera_mask & ~four, 0u);
}

TEST(PlaybackLoopOverRequests, ALateGopLowersTheNextFetches) {
  Rig rig;
  ASSERT_TRUE(rig.Tick().ok());
  rig.loop.FetchMeasured(62500, 1.0);
  for (int i = 0; i < 8 * 4; ++i) {
    while (rig.Serve() >= 0) {
    }
    ASSERT_TRUE(rig.Tick().ok());
  }
  const uint64_t before = rig.loop.FetchBudget();
  // Nothing held but the GOP shown, nothing served for a while: the playhead waits.
  const uint32_t shown = rig.loop.frame_index() / kGopFrames;
  for (uint32_t g = 0; g < kFrames / kGopFrames; ++g) {
    if (g != shown) rig.gops.Forget(g);
  }
  for (int i = 0; i < 30; ++i) ASSERT_TRUE(rig.Tick().ok());
  ASSERT_GE(rig.loop.stats().waits, 1u);
  EXPECT_LT(rig.loop.FetchBudget(), 0.75 * before);
}

TEST(PlaybackLoopOverRequests, AWaitForTheDecoderLeavesTheFetchesAlone) {
  Rig rig;
  ASSERT_TRUE(rig.Tick().ok());
  rig.loop.FetchMeasured(62500, 1.0);
  rig.Serve();
  ASSERT_TRUE(rig.Tick().ok());
  const uint64_t before = rig.loop.FetchBudget();
  uint32_t gop;
  GopRequest request;
  ASSERT_TRUE(rig.gops.NextRequest(&gop, &request));
  rig.gops.Fetched(gop);  // its bytes are in; it decodes for a long time
  // The start's preroll gives up on it after kMaxPrerollS, then GOP 0 plays.
  for (int i = 0; i < 60; ++i) ASSERT_TRUE(rig.Tick().ok());
  ASSERT_EQ(rig.loop.stats().waits, 1u);
  EXPECT_EQ(rig.loop.FetchBudget(), before) << "the network was not late";
}

TEST(PlaybackLoopOverRequests, ALateGopHoldsThePlayheadInsteadOfSkipping) {
  Rig rig;
  ASSERT_TRUE(rig.Tick().ok());
  rig.Serve();  // GOP 0
  ASSERT_TRUE(rig.Tick().ok());
  // GOP 1 is late: nothing is served for two seconds. The start's preroll
  // holds frame 0 for kMaxPrerollS of them, then GOP 0 plays and the
  // playhead waits at its end.
  for (int i = 0; i < 50; ++i) ASSERT_TRUE(rig.Tick().ok());
  EXPECT_EQ(rig.loop.frame_index(), kGopFrames - 1) << "the last frame of GOP 0 stays";
  EXPECT_EQ(rig.loop.stats().frames_advanced, kGopFrames - 1);
  rig.Serve();  // GOP 1 arrives
  ASSERT_TRUE(rig.Tick().ok());
  EXPECT_EQ(rig.loop.frame_index(), kGopFrames) << "played on from where it waited";
  EXPECT_EQ(rig.loop.stats().stalls, 1u);
  EXPECT_EQ(rig.loop.stats().waits, 1u) << "one wait, however many ticks it lasted";
}

// The GOP after the first decodes while the first frames are drawn: the
// playhead holds at the first frame until it is there (no wait, no stall
// counted), then plays through the GOP boundary without waiting.
TEST(PlaybackLoopOverRequests, TheStartHoldsTheFirstFrameUntilTheNextGopIsReady) {
  Rig rig;
  ASSERT_TRUE(rig.Tick().ok());
  rig.Serve();  // GOP 0 only
  ASSERT_TRUE(rig.Tick().ok());
  ASSERT_TRUE(rig.loop.has_frame());
  EXPECT_TRUE(rig.loop.prerolling());
  for (int i = 0; i < 10; ++i) ASSERT_TRUE(rig.Tick().ok());
  EXPECT_EQ(rig.loop.frame_index(), 0u);
  EXPECT_EQ(rig.loop.stats().frames_advanced, 0u);
  EXPECT_TRUE(rig.loop.prerolling());
  while (rig.Serve() >= 0) {
  }  // GOPs 1 and 2
  ASSERT_TRUE(rig.Tick().ok());
  EXPECT_FALSE(rig.loop.prerolling());
  for (int i = 0; i < 10; ++i) ASSERT_TRUE(rig.Tick().ok());
  EXPECT_GT(rig.loop.frame_index(), kGopFrames) << "through GOP 1 without a wait";
  EXPECT_EQ(rig.loop.stats().waits, 0u);
  EXPECT_EQ(rig.loop.stats().stalls, 0u) << "the hold was the start's, not a stall";
}

TEST(PlaybackLoopOverRequests, ASeekWaitsForItsGopAndIsNotLost) {
  Rig rig;
  ASSERT_TRUE(rig.Tick().ok());
  rig.Serve();
  ASSERT_TRUE(rig.Tick().ok());
  rig.loop.transport().playing = false;
  rig.loop.Seek(35);  // GOP 4, never asked for
  ASSERT_TRUE(rig.Tick().ok());
  EXPECT_EQ(rig.loop.frame_index(), 0u);
  uint32_t gop;
  GopRequest request;
  // What was queued ahead of the old playhead comes after the seek's GOP.
  ASSERT_TRUE(rig.gops.NextRequest(&gop, &request));
  EXPECT_EQ(gop, 4u);
  for (int i = 0; i < 5; ++i) ASSERT_TRUE(rig.Tick().ok());
  rig.gops.Deliver(gop, Whole());
  ASSERT_TRUE(rig.Tick().ok());
  EXPECT_EQ(rig.loop.frame_index(), 35u);
}

TEST(PlaybackLoopOverRequests, AFailedOrForgottenGopIsAskedForAgain) {
  Rig rig;
  ASSERT_TRUE(rig.Tick().ok());
  rig.Serve();
  ASSERT_TRUE(rig.Tick().ok());
  rig.loop.transport().playing = false;
  uint32_t gop;
  GopRequest request;
  ASSERT_TRUE(rig.gops.NextRequest(&gop, &request));
  ASSERT_EQ(gop, 1u);
  rig.gops.Failed(gop);  // the fetch failed: not held, not in flight
  ASSERT_EQ(rig.Serve(), 2);
  rig.gops.Forget(2);  // the embedding's cache dropped it
  EXPECT_FALSE(rig.gops.Held(2));
  rig.loop.Seek(8);
  ASSERT_TRUE(rig.Tick().ok());
  EXPECT_EQ(rig.Serve(), 1);
  ASSERT_TRUE(rig.Tick().ok());
  EXPECT_EQ(rig.loop.frame_index(), 8u);
  EXPECT_EQ(rig.Serve(), 2) << "asked for again, as the GOP ahead";
}

TEST(PlaybackLoopOverRequests, TwoFetchesRunAtOnceWhileThePlayheadWaitsForNeither) {
  Rig rig;
  ASSERT_TRUE(rig.Tick().ok());
  rig.Serve();
  ASSERT_TRUE(rig.Tick().ok());  // frame 0 shown: GOPs 1 and 2 asked for
  uint32_t gop, next, third;
  GopRequest request;
  ASSERT_TRUE(rig.gops.NextRequest(&gop, &request));
  ASSERT_TRUE(rig.gops.NextRequest(&next, &request)) << "the next GOP's fetch beside it";
  EXPECT_EQ(next, gop + 1);
  rig.loop.Seek(16);
  ASSERT_TRUE(rig.Tick().ok());  // GOP 2 is waited for now
  EXPECT_FALSE(rig.gops.NextRequest(&third, &request)) << "at most kFetchesInFlight";
  rig.gops.Fetched(gop);
  EXPECT_FALSE(rig.gops.NextRequest(&third, &request))
      << "none beside the fetch the playhead waits for";
  rig.gops.Fetched(next);
  ASSERT_TRUE(rig.gops.NextDecode(&third, &request));
  EXPECT_EQ(third, next) << "the GOP waited for decodes first";
  rig.gops.Deliver(next, Whole());
  ASSERT_TRUE(rig.Tick().ok());
  EXPECT_EQ(rig.loop.frame_index(), 16u);
}

TEST(PlaybackLoopOverRequests, FetchesRunFurtherAheadThanDecodes) {
  RequestedGops gops(kFrames, kGopFrames, /*fetch_ahead=*/4);
  PlaybackLoop loop(&gops, Info(), Ring());
  const glm::vec3 eye{0, 1, 3}, target{0, 1, 0};
  ASSERT_TRUE(loop.Advance(0.04, eye, target).ok());
  uint32_t gop;
  GopRequest r;
  std::vector<uint32_t> fetched, decoded;
  auto serve = [&] {
    while (gops.NextRequest(&gop, &r)) {
      fetched.push_back(gop);
      gops.Fetched(gop);
      while (gops.NextDecode(&gop, &r)) {
        decoded.push_back(gop);
        gops.Deliver(gop, Whole());
      }
    }
  };
  serve();
  ASSERT_TRUE(loop.Advance(0.04, eye, target).ok());  // frame 0 shown
  serve();
  EXPECT_EQ(fetched, (std::vector<uint32_t>{0, 1, 2, 3, 4}));
  EXPECT_EQ(decoded, (std::vector<uint32_t>{0, 1, 2})) << "decodes stop kAhead past the GOP shown";
  EXPECT_FALSE(gops.Arriving(3 * kGopFrames)) << "GOP 3's bytes are in";
  // The playhead reaches GOP 1: GOP 3 decodes from the bytes already there.
  for (int i = 0; i < 8; ++i) ASSERT_TRUE(loop.Advance(0.04, eye, target).ok());
  ASSERT_EQ(loop.frame_index(), kGopFrames);
  ASSERT_TRUE(gops.NextDecode(&gop, &r));
  EXPECT_EQ(gop, 3u);
}

}  // namespace
}  // namespace fvv
