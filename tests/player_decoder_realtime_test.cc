// The decoder under a real-time player's budgets: the quality floor a time
// budget never cuts through, and a GOP decoded ahead that a looping player's
// prefetch of the first GOP displaces (kept, not decoded again).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <thread>

#include "fvv/fvv_decoder.hpp"
#include "tests/sample_stream_file.h"

namespace fvv {
namespace {

// 3 spans of 4 frames, 2 cameras in a fragment each, 128x96 at 1 bpp: streams
// long enough that a deadline check (every few thousand decisions) comes well
// before the floors tested.
const std::string& StreamPath() {
  static const std::string* path = [] {
    SampleStreamOptions o;
    o.frames = 12;
    o.cameras = 2;
    o.atlas_width = 128;
    o.atlas_height = 96;
    o.gop_frames = 4;
    o.gop_cameras = 1;
    o.bpp = 1.0;
    return new std::string(WriteSampleStreamFile(o, "fvv_decoder_realtime_test.fvv"));
  }();
  return *path;
}

// Bytes decoded of frame `index`'s GOP with a time budget that runs out at once.
uint64_t BytesAtFloor(double floor_share, uint32_t index, uint64_t* available) {
  DecoderPtr dec = MakeDecoder();
  EXPECT_EQ(fvv_decoder_open_file(dec.get(), StreamPath().c_str()), FVV_OK);
  fvv_decode_budget budget{};
  budget.max_ms_per_gop = 1e-3;
  budget.floor_share = floor_share;
  FramePtr frame = DecodeFrame(dec.get(), index, &budget);
  EXPECT_TRUE(frame) << fvv_decoder_error(dec.get());
  if (!frame) return 0;
  *available = frame->report.bytes_available;
  return frame->report.bytes_decoded;
}

TEST(DecoderRealTime, TimeBudgetNeverCutsBelowTheFloor) {
  uint64_t available = 0;
  const uint64_t none = BytesAtFloor(0, 5, &available);
  ASSERT_GT(available, 10000u);
  EXPECT_LT(none, 0.1 * available);  // the time budget alone cuts almost everything
  uint64_t last = none;
  for (double share : {0.2, 0.5, 0.9}) {
    const uint64_t bytes = BytesAtFloor(share, 5, &available);
    EXPECT_GE(bytes, share * available) << share;
    EXPECT_LT(bytes, available) << share;  // the deadline still stops it past the floor
    EXPECT_GT(bytes, last) << share;
    last = bytes;
  }
  EXPECT_EQ(BytesAtFloor(1.0, 5, &available), available);
}

TEST(DecoderRealTime, FloorWithoutATimeBudgetChangesNothing) {
  DecoderPtr dec = MakeDecoder();
  ASSERT_EQ(fvv_decoder_open_file(dec.get(), StreamPath().c_str()), FVV_OK);
  fvv_decode_budget bytes_only{};
  bytes_only.max_bytes_per_gop = 1000;
  bytes_only.floor_share = 0.9;  // a floor belongs to time budgets only
  FramePtr frame = DecodeFrame(dec.get(), 0, &bytes_only);
  ASSERT_TRUE(frame);
  EXPECT_LE(frame->report.bytes_decoded, 2000u);  // 2 fragments of at most 1000 bytes
}

TEST(DecoderRealTime, FloorOutsideZeroToOneIsMisuse) {
  DecoderPtr dec = MakeDecoder();
  ASSERT_EQ(fvv_decoder_open_file(dec.get(), StreamPath().c_str()), FVV_OK);
  for (double bad : {-0.1, 1.5, std::numeric_limits<double>::quiet_NaN()}) {
    fvv_decode_budget budget{};
    budget.max_ms_per_gop = 10;
    budget.floor_share = bad;
    fvv_frame* frame = nullptr;
    EXPECT_EQ(fvv_decoder_decode_frame(dec.get(), 0, &budget, &frame), FVV_INVALID_ARGUMENT);
    EXPECT_EQ(frame, nullptr);
    EXPECT_NE(std::string(fvv_decoder_error(dec.get())).find("floor_share"), std::string::npos);
  }
}

bool WaitReady(fvv_decoder* dec, uint32_t frame, const fvv_decode_budget& budget) {
  for (int i = 0; i < 1000; ++i) {
    if (fvv_decoder_frame_ready(dec, frame, &budget)) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return false;
}

// Playing span 1 with span 2 decoded ahead, a looping player asks for span 0:
// span 2 is kept (ready at once, and the decode it took is the one reported),
// span 0 decodes beside it, and asking for span 2 does not drop span 0's decode.
TEST(DecoderRealTime, APrefetchKeepsTheGopDecodedAheadItDisplaces) {
  DecoderPtr dec = MakeDecoder();
  ASSERT_EQ(fvv_decoder_open_file(dec.get(), StreamPath().c_str()), FVV_OK);
  fvv_decode_budget budget{};
  budget.max_ms_per_gop = 1000;
  budget.floor_share = 0.15;
  FramePtr playing = DecodeFrame(dec.get(), 4, &budget);  // span 1; span 2 decodes ahead
  ASSERT_TRUE(playing);
  ASSERT_TRUE(WaitReady(dec.get(), 8, budget));
  ASSERT_EQ(fvv_decoder_prefetch(dec.get(), 0, &budget), FVV_OK);  // the loop's first GOP
  EXPECT_TRUE(fvv_decoder_frame_ready(dec.get(), 8, &budget));     // kept
  ASSERT_TRUE(WaitReady(dec.get(), 0, budget));
  FramePtr last = DecodeFrame(dec.get(), 9, &budget);
  ASSERT_TRUE(last);
  EXPECT_TRUE(fvv_decoder_frame_ready(dec.get(), 0, &budget));  // still there
  FramePtr first = DecodeFrame(dec.get(), 0, &budget);
  ASSERT_TRUE(first);
  EXPECT_EQ(first->index, 0u);
  EXPECT_TRUE(first->report.complete);
}

}  // namespace
}  // namespace fvv
