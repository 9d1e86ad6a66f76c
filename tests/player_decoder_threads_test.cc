// The decoder's C API under threads, as fvv_decoder.h documents it: several
// decoders on separate threads at once, and one decoder handed from thread to
// thread (one at a time) while its workers decode ahead, its frames read and
// released on yet other threads, some after the decoder is gone. Every frame
// must equal a single-threaded decode's. Built under ThreadSanitizer by
// tools/test.sh, where any data race fails it.
#include <gtest/gtest.h>

#include <atomic>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <mutex>
#include <thread>
#include <vector>

#include "conformance/sample/sample_stream.h"
#include "container/writer.h"
#include "fvv/fvv_decoder.hpp"

namespace fvv {
namespace {

constexpr uint32_t kFrames = 12, kCameras = 3;

struct Reference {
  std::string path;
  std::vector<uint8_t> bytes;
  // Per frame, per camera: RGB of a full single-threaded decode.
  std::vector<std::vector<std::vector<uint8_t>>> pixels;
  std::vector<std::vector<float>> bones;  // per frame: bone_world
  size_t plane = 0;                       // bytes of one camera's RGB
};

const Reference& Shared() {
  static const Reference* r = [] {
    auto* ref = new Reference;
    SampleStreamOptions o;
    o.frames = kFrames;
    o.cameras = kCameras;
    o.atlas_width = 48;
    o.atlas_height = 32;
    o.gop_frames = 4;
    o.gop_cameras = 1;
    o.bpp = 2.0;
    StatusOr<SampleStream> s = MakeSampleStream(o);
    EXPECT_TRUE(s.ok());
    ref->path = ::testing::TempDir() + "/fvv_decoder_threads_test.fvv";
    auto w = FileWriter::Create(ref->path, s->info);
    EXPECT_TRUE(w.ok());
    for (const auto& frag : s->fragments) EXPECT_TRUE((*w)->AddFragment(frag).ok());
    EXPECT_TRUE((*w)->Close().ok());
    ref->bytes = *WriteStreamToMemory(s->info, s->fragments);
    fvv_decoder_settings settings;
    fvv_decoder_default_settings(&settings);
    settings.threads = 1;
    settings.decode_ahead = 0;
    DecoderPtr dec = MakeDecoder(&settings);
    EXPECT_EQ(fvv_decoder_open_file(dec.get(), ref->path.c_str()), FVV_OK);
    for (uint32_t f = 0; f < kFrames; ++f) {
      FramePtr frame = DecodeFrame(dec.get(), f, nullptr);
      EXPECT_TRUE(frame);
      ref->plane = size_t{frame->width} * frame->height * 3;
      ref->pixels.emplace_back();
      for (uint32_t c = 0; c < kCameras; ++c) {
        ref->pixels.back().emplace_back(frame->views[c].pixels,
                                        frame->views[c].pixels + ref->plane);
      }
      ref->bones.emplace_back(frame->bone_world, frame->bone_world + frame->bone_count * 16);
    }
    return ref;
  }();
  return *r;
}

// Whether a full decode's frame equals the reference (pixels and bones).
bool MatchesReference(const fvv_frame& frame) {
  const Reference& ref = Shared();
  if (frame.index >= kFrames || frame.camera_count != kCameras) return false;
  for (uint32_t c = 0; c < kCameras; ++c) {
    if (!frame.views[c].pixels ||
        std::memcmp(frame.views[c].pixels, ref.pixels[frame.index][c].data(), ref.plane) != 0) {
      return false;
    }
  }
  return std::memcmp(frame.bone_world, ref.bones[frame.index].data(),
                     ref.bones[frame.index].size() * sizeof(float)) == 0;
}

DecoderPtr Threaded(int decode_ahead) {
  fvv_decoder_settings settings;
  fvv_decoder_default_settings(&settings);
  settings.threads = 2;
  settings.decode_ahead = decode_ahead;
  return MakeDecoder(&settings);
}

// Four decoders at once, each on its own thread with its own workers: two
// read the file forwards and backwards, one under changing budgets, one is
// pushed the bytes in pieces.
TEST(DecoderThreads, SeveralDecodersOnSeparateThreads) {
  const Reference& ref = Shared();
  std::atomic<int> mismatches{0}, failures{0};
  auto forwards = [&](bool backwards) {
    DecoderPtr dec = Threaded(1);
    if (!dec || fvv_decoder_open_file(dec.get(), ref.path.c_str()) != FVV_OK)
      return ++failures, void();
    for (int round = 0; round < 3; ++round) {
      for (uint32_t i = 0; i < kFrames; ++i) {
        const uint32_t f = backwards ? kFrames - 1 - i : i;
        FramePtr frame = DecodeFrame(dec.get(), f, nullptr);
        if (!frame) return ++failures, void();
        if (!MatchesReference(*frame)) ++mismatches;
      }
    }
  };
  auto budgets = [&] {
    DecoderPtr dec = Threaded(1);
    if (!dec || fvv_decoder_open_file(dec.get(), ref.path.c_str()) != FVV_OK)
      return ++failures, void();
    for (uint32_t f = 0; f < kFrames; ++f) {
      fvv_decode_budget budget{};
      budget.max_bytes_per_gop = 200 + 100 * f;
      budget.camera_mask = 1u << (f % kCameras);
      fvv_decoder_prefetch(dec.get(), (f + 1) % kFrames, &budget);
      FramePtr cut = DecodeFrame(dec.get(), f, &budget);
      FramePtr full = DecodeFrame(dec.get(), f, nullptr);
      if (!cut || !full) return ++failures, void();
      if (!MatchesReference(*full)) ++mismatches;
      if (cut->report.bytes_decoded > full->report.bytes_decoded) ++mismatches;
    }
  };
  auto pushed = [&] {
    DecoderPtr dec = Threaded(1);
    if (!dec) return ++failures, void();
    size_t pos = 0;
    uint32_t decoded = 0;
    for (bool ended = false; !ended;) {
      fvv_event event;
      if (fvv_decoder_process(dec.get(), &event) != FVV_OK) return ++failures, void();
      if (event == FVV_EVENT_NEED_MORE_INPUT) {
        if (pos == ref.bytes.size()) {
          fvv_decoder_push_end(dec.get());
        } else {
          const size_t n = std::min<size_t>(1000, ref.bytes.size() - pos);
          fvv_decoder_push(dec.get(), ref.bytes.data() + pos, n);
          pos += n;
        }
      } else if (event == FVV_EVENT_FRAMES) {
        for (; decoded < fvv_decoder_frames_available(dec.get()); ++decoded) {
          FramePtr frame = DecodeFrame(dec.get(), decoded, nullptr);
          if (!frame) return ++failures, void();
          if (!MatchesReference(*frame)) ++mismatches;
        }
      } else if (event == FVV_EVENT_END) {
        ended = true;
      }
    }
    if (decoded != kFrames) ++failures;
  };
  std::vector<std::thread> threads;
  threads.emplace_back(forwards, false);
  threads.emplace_back(forwards, true);
  threads.emplace_back(budgets);
  threads.emplace_back(pushed);
  for (std::thread& t : threads) t.join();
  EXPECT_EQ(failures.load(), 0);
  EXPECT_EQ(mismatches.load(), 0);
}

// One decoder, its calls made by three threads in turn (a mutex hands it on,
// so calls never overlap, as documented) while its worker decodes the next
// GOP ahead; each frame goes to a reader thread, which checks and releases
// it. The decoder is destroyed while the last frames are still held; they
// stay readable.
TEST(DecoderThreads, OneDecoderHandedBetweenThreads) {
  const Reference& ref = Shared();
  DecoderPtr dec = Threaded(1);
  ASSERT_TRUE(dec);
  ASSERT_EQ(fvv_decoder_open_file(dec.get(), ref.path.c_str()), FVV_OK);
  std::mutex decoder_mutex, queue_mutex;
  std::condition_variable queued;
  std::deque<fvv_frame*> frames;
  bool callers_done = false;
  std::atomic<int> mismatches{0}, failures{0}, read{0};
  std::atomic<uint32_t> next{0};
  constexpr uint32_t kCalls = 3 * kFrames;
  auto caller = [&] {
    for (;;) {
      std::lock_guard<std::mutex> lock(decoder_mutex);
      const uint32_t call = next++;
      if (call >= kCalls) return;
      const uint32_t f = (call * 5) % kFrames;  // jumps across GOPs, as a scrubbing user does
      fvv_decoder_prefetch(dec.get(), (f + 4) % kFrames, nullptr);
      fvv_frame* frame = nullptr;
      if (fvv_decoder_decode_frame(dec.get(), f, nullptr, &frame) != FVV_OK) {
        ++failures;
        continue;
      }
      std::lock_guard<std::mutex> q(queue_mutex);
      frames.push_back(frame);
      queued.notify_one();
    }
  };
  auto reader = [&] {
    for (;;) {
      fvv_frame* frame = nullptr;
      {
        std::unique_lock<std::mutex> q(queue_mutex);
        queued.wait(q, [&] { return !frames.empty() || callers_done; });
        if (frames.empty()) return;
        frame = frames.front();
        frames.pop_front();
      }
      if (!MatchesReference(*frame)) ++mismatches;
      ++read;
      fvv_frame_release(frame);
    }
  };
  std::vector<std::thread> callers, readers;
  for (int i = 0; i < 2; ++i) readers.emplace_back(reader);
  for (int i = 0; i < 3; ++i) callers.emplace_back(caller);
  for (std::thread& t : callers) t.join();
  // The last GOP's frames, taken now and read after the decoder is gone.
  std::vector<FramePtr> kept;
  for (uint32_t f = kFrames - 4; f < kFrames; ++f)
    kept.push_back(DecodeFrame(dec.get(), f, nullptr));
  dec.reset();
  {
    std::lock_guard<std::mutex> q(queue_mutex);
    callers_done = true;
    queued.notify_all();
  }
  for (std::thread& t : readers) t.join();
  std::thread late([&] {
    for (const FramePtr& frame : kept) {
      if (!frame || !MatchesReference(*frame)) ++mismatches;
    }
  });
  late.join();
  EXPECT_EQ(failures.load(), 0);
  EXPECT_EQ(read.load(), int(kCalls));
  EXPECT_EQ(mismatches.load(), 0);
}

}  // namespace
}  // namespace fvv
