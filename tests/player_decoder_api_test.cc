// The decoder library through its C API: stream info, model, poses, textures
// and masks against the source; budgets; streaming input; misuse and bad
// streams give status codes.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <thread>
#include <vector>

#include "codec/colour.h"
#include "conformance/sample/sample_stream.h"
#include "container/writer.h"
#include "fvv/fvv_decoder.hpp"
#include "player/decoder/c_api_internal.h"
#include "tests/sample_stream_file.h"

extern "C" int fvv_public_headers_compile_as_c(void);

namespace fvv {
namespace {

SampleStreamOptions Options() {
  SampleStreamOptions o;
  o.frames = 10;
  o.cameras = 3;
  o.atlas_width = 32;
  o.atlas_height = 24;
  o.gop_frames = 4;
  o.gop_cameras = 2;
  o.bpp = 2.0;
  return o;
}

struct Fixture {
  SampleStream sample;
  std::string path;
  std::vector<uint8_t> bytes;
};

const Fixture& Shared() {
  static const Fixture* f = [] {
    auto* fx = new Fixture;
    auto s = MakeSampleStream(Options());
    EXPECT_TRUE(s.ok());
    fx->sample = std::move(s).value();
    fx->path = ::testing::TempDir() + "/fvv_decoder_api_test.fvv";
    auto w = FileWriter::Create(fx->path, fx->sample.info);
    EXPECT_TRUE(w.ok());
    for (const auto& frag : fx->sample.fragments) EXPECT_TRUE((*w)->AddFragment(frag).ok());
    EXPECT_TRUE((*w)->Close().ok());
    fx->bytes = *WriteStreamToMemory(fx->sample.info, fx->sample.fragments);
    return fx;
  }();
  return *f;
}

double UsedPsnr(const fvv_frame& frame, const Fixture& fx) {
  const size_t texels = size_t{frame.width} * frame.height;
  double sum = 0;
  size_t n = 0;
  for (uint32_t c = 0; c < frame.camera_count; ++c) {
    const size_t plane = size_t{frame.index} * frame.camera_count + c;
    for (size_t i = 0; i < texels; ++i) {
      if (!fx.sample.masks[plane * texels + i]) continue;
      for (int k = 0; k < 3; ++k) {
        const double d =
            double(frame.views[c].pixels[3 * i + k]) - fx.sample.rgb[(plane * texels + i) * 3 + k];
        sum += d * d;
        ++n;
      }
    }
  }
  return 10 * std::log10(255.0 * 255.0 / std::max(1e-9, sum / n));
}

// Polls for up to 5 s until `frame` is ready under `budget`; `ask_again`
// repeats the prefetch each time, as a player's loop does.
void WaitUntilReady(fvv_decoder* dec, uint32_t frame, const fvv_decode_budget& budget,
                    bool ask_again) {
  for (int i = 0; i < 500 && !fvv_decoder_frame_ready(dec, frame, &budget); ++i) {
    if (ask_again) fvv_decoder_prefetch(dec, frame, &budget);
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

TEST(DecoderApi, PublicHeadersCompileAsC) { EXPECT_EQ(fvv_public_headers_compile_as_c(), 1); }

TEST(DecoderApi, FileDecodeMatchesTheSource) {
  const Fixture& fx = Shared();
  DecoderPtr dec = MakeDecoder();
  ASSERT_TRUE(dec);
  ASSERT_EQ(fvv_decoder_open_file(dec.get(), fx.path.c_str()), FVV_OK)
      << fvv_decoder_error(dec.get());
  fvv_stream_info info;
  ASSERT_EQ(fvv_decoder_get_info(dec.get(), &info), FVV_OK);
  EXPECT_EQ(info.frame_count, 10u);
  EXPECT_EQ(info.camera_count, 3u);
  EXPECT_EQ(info.atlas_width, 32u);
  EXPECT_EQ(info.bone_count, 15u);
  EXPECT_TRUE(info.has_masks);
  fvv_camera cam;
  ASSERT_EQ(fvv_decoder_get_camera(dec.get(), 2, &cam), FVV_OK);
  EXPECT_STREQ(cam.name, "cam2");
  fvv_model model;
  ASSERT_EQ(fvv_decoder_get_model(dec.get(), &model), FVV_OK);
  EXPECT_EQ(model.vertex_count, fx.sample.info.model.mesh.positions.size());
  EXPECT_FLOAT_EQ(model.weights[0], 1.0f);
  EXPECT_FLOAT_EQ(model.bone_rest_world[13], 0.95f);  // pelvis joint height

  const std::vector<DofRef> dofs = fx.sample.info.model.skeleton.Dofs();
  for (uint32_t f = 0; f < info.frame_count; ++f) {
    FramePtr frame = DecodeFrame(dec.get(), f, nullptr);
    ASSERT_TRUE(frame) << fvv_decoder_error(dec.get());
    EXPECT_EQ(frame->index, f);
    EXPECT_TRUE(frame->report.complete);
    EXPECT_EQ(frame->report.bytes_decoded, frame->report.bytes_available);
    // Textures over used texels, at 2 bpp.
    EXPECT_GT(UsedPsnr(*frame, fx), 30.0) << "frame " << f;
    // Masks exactly.
    const size_t texels = size_t{frame->width} * frame->height;
    for (uint32_t c = 0; c < frame->camera_count; ++c) {
      ASSERT_NE(frame->views[c].mask, nullptr);
      for (size_t i = 0; i < texels; ++i) {
        ASSERT_EQ(frame->views[c].mask[i], fx.sample.masks[(size_t{f} * 3 + c) * texels + i]);
      }
    }
    // The root's world translation: rest offset + the walk's translation DOFs,
    // within half a translation step.
    const std::vector<double> truth = SampleWalkPose(fx.sample.info.model.skeleton, f);
    const float* root = frame->bone_world;  // bone 0, column-major
    EXPECT_NEAR(root[12], truth[3], 0.00026);
    EXPECT_NEAR(root[13], 0.95 + truth[4], 0.00026);
    EXPECT_NEAR(root[14], truth[5], 0.00026);
  }
}

// RGB8 output is the spec's colour conversion (9.7) of the YUV output, exactly
// (the library converts rows with a vectorised 32-bit form of it).
TEST(DecoderApi, Rgb8IsTheSpecConversionOfYuv444) {
  const Fixture& fx = Shared();
  DecoderPtr dec = MakeDecoder();
  ASSERT_EQ(fvv_decoder_open_file(dec.get(), fx.path.c_str()), FVV_OK);
  fvv_decode_budget rgb{}, yuv{};
  yuv.format = FVV_FORMAT_YUV444;
  for (uint32_t f : {0u, 5u, 9u}) {
    FramePtr a = DecodeFrame(dec.get(), f, &rgb);
    ASSERT_TRUE(a) << fvv_decoder_error(dec.get());
    FramePtr b = DecodeFrame(dec.get(), f, &yuv);
    ASSERT_TRUE(b) << fvv_decoder_error(dec.get());
    const size_t texels = size_t{a->width} * a->height;
    for (uint32_t c = 0; c < a->camera_count; ++c) {
      const uint8_t* p = b->views[c].pixels;
      for (size_t i = 0; i < texels; ++i) {
        const Rgb8 e = YuvToRgb(ColourSpace::kYCbCr601, p[i], p[texels + i], p[2 * texels + i]);
        const uint8_t* got = a->views[c].pixels + 3 * i;
        ASSERT_TRUE(got[0] == e.r && got[1] == e.g && got[2] == e.b)
            << "frame " << f << " camera " << c << " texel " << i;
      }
    }
  }
}

// A decoder reuses the texture buffers of GOPs it dropped: frames decoded
// forward and then backward (every GOP after the first two on recycled buffers)
// equal those of a decoder that decodes each frame afresh.
TEST(DecoderApi, RecycledGopBuffersGiveTheSameFrames) {
  const Fixture& fx = Shared();
  fvv_decode_budget yuv{};
  yuv.format = FVV_FORMAT_YUV444;
  auto frame_bytes = [](const fvv_frame& f) {
    std::vector<uint8_t> out;
    const size_t n = size_t{f.width} * f.height * 3;
    for (uint32_t c = 0; c < f.camera_count; ++c)
      out.insert(out.end(), f.views[c].pixels, f.views[c].pixels + n);
    return out;
  };
  DecoderPtr dec = MakeDecoder();
  ASSERT_EQ(fvv_decoder_open_file(dec.get(), fx.path.c_str()), FVV_OK);
  std::vector<uint32_t> order;
  for (uint32_t f = 0; f < 10; ++f) order.push_back(f);
  for (uint32_t f = 10; f-- > 0;) order.push_back(f);
  for (uint32_t f : order) {
    FramePtr got = DecodeFrame(dec.get(), f, &yuv);
    ASSERT_TRUE(got) << fvv_decoder_error(dec.get());
    DecoderPtr alone = MakeDecoder();
    ASSERT_EQ(fvv_decoder_open_file(alone.get(), fx.path.c_str()), FVV_OK);
    FramePtr expected = DecodeFrame(alone.get(), f, &yuv);
    ASSERT_TRUE(expected) << fvv_decoder_error(alone.get());
    ASSERT_EQ(frame_bytes(*got), frame_bytes(*expected)) << "frame " << f;
  }
}

TEST(DecoderApi, ByteBudgetIsRespectedAndLowersQuality) {
  const Fixture& fx = Shared();
  DecoderPtr dec = MakeDecoder();
  ASSERT_EQ(fvv_decoder_open_file(dec.get(), fx.path.c_str()), FVV_OK);
  FramePtr full = DecodeFrame(dec.get(), 5, nullptr);
  ASSERT_TRUE(full);
  const double full_psnr = UsedPsnr(*full, fx);
  ASSERT_GT(full->report.bytes_available,
            2000u);  // fragments of ~1500 and ~750 bytes: all cut below
  for (uint64_t k : {60u, 200u, 500u}) {
    fvv_decode_budget budget{};
    budget.max_bytes_per_gop = k;
    FramePtr cut = DecodeFrame(dec.get(), 5, &budget);
    ASSERT_TRUE(cut) << fvv_decoder_error(dec.get());
    const uint64_t fragments = 2;  // camera groups of the span
    EXPECT_LE(cut->report.bytes_decoded, k * fragments);
    EXPECT_FALSE(cut->report.complete);
    EXPECT_LT(UsedPsnr(*cut, fx), full_psnr);
  }
  fvv_decode_budget timed{};
  timed.max_ms_per_gop = 1e-3;  // stops almost at once: still a valid, coarse frame
  FramePtr quick = DecodeFrame(dec.get(), 9, &timed);
  ASSERT_TRUE(quick);
  EXPECT_LT(quick->report.bytes_decoded, quick->report.bytes_available);
}

TEST(DecoderApi, StreamingGivesTheSameFrames) {
  const Fixture& fx = Shared();
  DecoderPtr file = MakeDecoder();
  ASSERT_EQ(fvv_decoder_open_file(file.get(), fx.path.c_str()), FVV_OK);
  fvv_decoder_settings settings;
  fvv_decoder_default_settings(&settings);
  settings.decode_ahead = 0;
  DecoderPtr dec = MakeDecoder(&settings);
  size_t pos = 0;
  bool ready = false, ended = false;
  uint32_t decoded = 0;
  while (!ended) {
    fvv_event event;
    ASSERT_EQ(fvv_decoder_process(dec.get(), &event), FVV_OK) << fvv_decoder_error(dec.get());
    if (event == FVV_EVENT_NEED_MORE_INPUT) {
      if (pos == fx.bytes.size()) {
        ASSERT_EQ(fvv_decoder_push_end(dec.get()), FVV_OK);
      } else {
        const size_t n = std::min<size_t>(777, fx.bytes.size() - pos);
        ASSERT_EQ(fvv_decoder_push(dec.get(), fx.bytes.data() + pos, n), FVV_OK);
        pos += n;
      }
    } else if (event == FVV_EVENT_READY) {
      ready = true;
    } else if (event == FVV_EVENT_FRAMES) {
      ASSERT_TRUE(ready);
      for (; decoded < fvv_decoder_frames_available(dec.get()); ++decoded) {
        FramePtr a = DecodeFrame(dec.get(), decoded, nullptr);
        FramePtr b = DecodeFrame(file.get(), decoded, nullptr);
        ASSERT_TRUE(a && b);
        for (uint32_t c = 0; c < a->camera_count; ++c) {
          ASSERT_EQ(0, std::memcmp(a->views[c].pixels, b->views[c].pixels,
                                   size_t{a->width} * a->height * 3));
        }
        ASSERT_EQ(0, std::memcmp(a->bone_world, b->bone_world, a->bone_count * 16 * sizeof(float)));
      }
    } else if (event == FVV_EVENT_END) {
      ended = true;
    }
  }
  EXPECT_EQ(decoded, 10u);
}

// A live stream (no frame count in its header) opened as a file has the
// frames of its fragments (SPEC.md 3.1), as pushed it has once it ends: the
// conformance case `live`, 9 frames in spans of 4.
TEST(DecoderApi, ALiveStreamFileHasTheFramesOfItsFragments) {
  const std::string path = std::string(FVV_CONFORMANCE_DIR) + "/live/stream.fvv";
  DecoderPtr file = MakeDecoder();
  ASSERT_EQ(fvv_decoder_open_file(file.get(), path.c_str()), FVV_OK)
      << fvv_decoder_error(file.get());
  fvv_stream_info info;
  ASSERT_EQ(fvv_decoder_get_info(file.get(), &info), FVV_OK);
  EXPECT_EQ(info.frame_count, 0u);  // the header's: not known when it was written
  EXPECT_EQ(fvv_decoder_frames_available(file.get()), 9u);
  FramePtr last = DecodeFrame(file.get(), 8, nullptr);
  ASSERT_TRUE(last) << fvv_decoder_error(file.get());
  EXPECT_FALSE(DecodeFrame(file.get(), 9, nullptr));

  std::ifstream in(path, std::ios::binary);
  const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                   std::istreambuf_iterator<char>());
  DecoderPtr pushed = MakeDecoder();
  ASSERT_EQ(fvv_decoder_push(pushed.get(), bytes.data(), bytes.size()), FVV_OK);
  ASSERT_EQ(fvv_decoder_push_end(pushed.get()), FVV_OK);
  for (fvv_event event = FVV_EVENT_NEED_MORE_INPUT; event != FVV_EVENT_END;) {
    ASSERT_EQ(fvv_decoder_process(pushed.get(), &event), FVV_OK) << fvv_decoder_error(pushed.get());
  }
  EXPECT_EQ(fvv_decoder_frames_available(pushed.get()), 9u);
  FramePtr same = DecodeFrame(pushed.get(), 8, nullptr);
  ASSERT_TRUE(same);
  for (uint32_t c = 0; c < last->camera_count; ++c) {
    EXPECT_EQ(0, std::memcmp(last->views[c].pixels, same->views[c].pixels,
                             size_t{last->width} * last->height * 3));
  }
}

TEST(DecoderApi, PrefetchMakesAFrameReadyWithoutBlocking) {
  const Fixture& fx = Shared();
  fvv_decoder_settings settings;
  fvv_decoder_default_settings(&settings);
  settings.decode_ahead = 0;
  DecoderPtr dec = MakeDecoder(&settings);
  ASSERT_EQ(fvv_decoder_open_file(dec.get(), fx.path.c_str()), FVV_OK);
  fvv_decode_budget budget{};
  budget.max_ms_per_gop = 1000;
  EXPECT_FALSE(fvv_decoder_frame_ready(dec.get(), 5, &budget));
  ASSERT_EQ(fvv_decoder_prefetch(dec.get(), 5, &budget), FVV_OK);
  WaitUntilReady(dec.get(), 5, budget, /*ask_again=*/false);
  ASSERT_TRUE(fvv_decoder_frame_ready(dec.get(), 5, &budget));
  EXPECT_TRUE(fvv_decoder_frame_ready(dec.get(), 6, &budget));   // same GOP
  EXPECT_FALSE(fvv_decoder_frame_ready(dec.get(), 9, &budget));  // the next one
  FramePtr frame = DecodeFrame(dec.get(), 6, &budget);
  ASSERT_TRUE(frame);
  EXPECT_EQ(frame->index, 6u);
  EXPECT_EQ(fvv_decoder_prefetch(dec.get(), 10, &budget), FVV_INVALID_ARGUMENT);
  EXPECT_EQ(fvv_decoder_prefetch(nullptr, 0, &budget), FVV_INVALID_ARGUMENT);
  EXPECT_FALSE(fvv_decoder_frame_ready(nullptr, 0, &budget));
}

// A camera mask decodes only the camera groups it names: their textures are
// those of a full decode, the others come back NULL; a GOP holding more cameras
// serves a narrower request; prefetching with a mask that the decode under way
// does not serve starts a decode that does.
TEST(DecoderApi, CameraMaskDecodesOnlyTheCameraGroupsAsked) {
  const Fixture& fx = Shared();  // 3 cameras in groups {0, 1} and {2}
  DecoderPtr full_dec = MakeDecoder();
  ASSERT_EQ(fvv_decoder_open_file(full_dec.get(), fx.path.c_str()), FVV_OK);
  FramePtr full = DecodeFrame(full_dec.get(), 5, nullptr);
  ASSERT_TRUE(full);
  const size_t bytes = size_t{full->width} * full->height * 3;

  fvv_decoder_settings settings;
  fvv_decoder_default_settings(&settings);
  settings.decode_ahead = 0;
  DecoderPtr dec = MakeDecoder(&settings);
  ASSERT_EQ(fvv_decoder_open_file(dec.get(), fx.path.c_str()), FVV_OK);
  fvv_decode_budget only2{};
  only2.camera_mask = 1u << 2;
  FramePtr part = DecodeFrame(dec.get(), 5, &only2);
  ASSERT_TRUE(part) << fvv_decoder_error(dec.get());
  EXPECT_EQ(part->views[0].pixels, nullptr);
  EXPECT_EQ(part->views[1].pixels, nullptr);
  EXPECT_EQ(part->views[0].mask, nullptr);
  ASSERT_NE(part->views[2].pixels, nullptr);
  EXPECT_EQ(std::memcmp(part->views[2].pixels, full->views[2].pixels, bytes), 0);
  EXPECT_LT(part->report.bytes_decoded, full->report.bytes_decoded);
  EXPECT_GT(part->report.bytes_decoded, 0u);

  // Camera 0 alone brings its whole group {0, 1}.
  fvv_decode_budget only0{};
  only0.camera_mask = 1u;
  FramePtr group = DecodeFrame(dec.get(), 0, &only0);
  ASSERT_TRUE(group);
  ASSERT_NE(group->views[1].pixels, nullptr);
  EXPECT_EQ(group->views[2].pixels, nullptr);
  // The same GOP asked for camera 1 only: served by what was decoded.
  fvv_decode_budget only1{};
  only1.camera_mask = 1u << 1;
  EXPECT_TRUE(fvv_decoder_frame_ready(dec.get(), 1, &only1));
  // ... but not for camera 2, which needs a decode.
  EXPECT_FALSE(fvv_decoder_frame_ready(dec.get(), 1, &only2));
  ASSERT_EQ(fvv_decoder_prefetch(dec.get(), 1, &only2), FVV_OK);
  WaitUntilReady(dec.get(), 1, only2, /*ask_again=*/false);
  EXPECT_TRUE(fvv_decoder_frame_ready(dec.get(), 1, &only2));
  // A prefetch under way for one mask, then another mask for the same GOP: the
  // second must still become ready (it is not served by the first).
  ASSERT_EQ(fvv_decoder_prefetch(dec.get(), 9, &only0), FVV_OK);
  ASSERT_EQ(fvv_decoder_prefetch(dec.get(), 9, &only2), FVV_OK);
  WaitUntilReady(dec.get(), 9, only2, /*ask_again=*/true);  // as a player asks each frame
  EXPECT_TRUE(fvv_decoder_frame_ready(dec.get(), 9, &only2));

  fvv_decode_budget beyond{};
  beyond.camera_mask = 1u << 3;  // the stream has 3 cameras
  fvv_frame* frame = nullptr;
  EXPECT_EQ(fvv_decoder_decode_frame(dec.get(), 0, &beyond, &frame), FVV_INVALID_ARGUMENT);
}

TEST(DecoderApi, MisuseGivesInvalidArgument) {
  EXPECT_EQ(fvv_decoder_create(nullptr, nullptr), FVV_INVALID_ARGUMENT);
  DecoderPtr dec = MakeDecoder();
  fvv_stream_info info;
  fvv_event event;
  fvv_frame* frame = nullptr;
  EXPECT_EQ(fvv_decoder_get_info(dec.get(), &info), FVV_INVALID_ARGUMENT);
  ASSERT_EQ(fvv_decoder_process(dec.get(), &event), FVV_OK);  // streaming starts empty
  EXPECT_EQ(event, FVV_EVENT_NEED_MORE_INPUT);
  EXPECT_EQ(fvv_decoder_decode_frame(dec.get(), 0, nullptr, &frame), FVV_INVALID_ARGUMENT);
  EXPECT_STRNE(fvv_decoder_error(dec.get()), "");
  EXPECT_EQ(fvv_decoder_get_info(nullptr, &info), FVV_INVALID_ARGUMENT);
  EXPECT_EQ(fvv_decoder_open_file(dec.get(), nullptr), FVV_INVALID_ARGUMENT);
  EXPECT_EQ(fvv_decoder_open_file(dec.get(), "/nonexistent/x.fvv"), FVV_IO_ERROR);
  DecoderPtr other = MakeDecoder();
  dec.swap(other);  // a fresh decoder: the one above is a streaming decoder now
  ASSERT_EQ(fvv_decoder_open_file(dec.get(), Shared().path.c_str()), FVV_OK);
  const uint8_t byte = 0;
  EXPECT_EQ(fvv_decoder_push(dec.get(), &byte, 1), FVV_INVALID_ARGUMENT);  // one input only
  EXPECT_EQ(fvv_decoder_decode_frame(dec.get(), 10, nullptr, &frame), FVV_INVALID_ARGUMENT);
  fvv_decode_budget bad{};
  bad.format = 7;
  EXPECT_EQ(fvv_decoder_decode_frame(dec.get(), 0, &bad, &frame), FVV_INVALID_ARGUMENT);
  fvv_camera cam;
  EXPECT_EQ(fvv_decoder_get_camera(dec.get(), 3, &cam), FVV_INVALID_ARGUMENT);
  EXPECT_EQ(frame, nullptr);
  fvv_frame_release(nullptr);
  fvv_decoder_destroy(nullptr);
  EXPECT_STREQ(fvv_status_name(FVV_CHECKSUM_MISMATCH), "checksum mismatch");
}

// A directory opens like a file and reports a size it does not have; the
// decoder must say what it is, and programs carry the code on (c_api_internal.h).
TEST(DecoderApi, ADirectoryIsNotAStream) {
  DecoderPtr dec = MakeDecoder();
  const std::string dir = ::testing::TempDir();
  EXPECT_EQ(fvv_decoder_open_file(dec.get(), dir.c_str()), FVV_IO_ERROR);
  EXPECT_NE(std::strstr(fvv_decoder_error(dec.get()), "not a regular file"), nullptr)
      << fvv_decoder_error(dec.get());
  const Status s = DecoderStatus(dec.get());
  EXPECT_EQ(s.code(), StatusCode::kIoError);
  EXPECT_EQ(s.ToString(), fvv_decoder_error(dec.get()));
}

TEST(DecoderApi, DamagedFragmentIsReportedAndOthersStillDecode) {
  const Fixture& fx = Shared();
  std::vector<uint8_t> bad = fx.bytes;
  bad[bad.size() - 200] ^= 0x40;  // inside the last fragment (before the end index? no: fast start)
  const std::string path = ::testing::TempDir() + "/fvv_decoder_api_damaged.fvv";
  FILE* f = std::fopen(path.c_str(), "wb");
  ASSERT_NE(f, nullptr);
  ASSERT_EQ(std::fwrite(bad.data(), 1, bad.size(), f), bad.size());
  std::fclose(f);
  DecoderPtr dec = MakeDecoder();
  ASSERT_EQ(fvv_decoder_open_file(dec.get(), path.c_str()), FVV_OK);
  fvv_frame* frame = nullptr;
  EXPECT_EQ(fvv_decoder_decode_frame(dec.get(), 9, nullptr, &frame), FVV_CHECKSUM_MISMATCH);
  EXPECT_NE(std::string(fvv_decoder_error(dec.get())).find("frag"), std::string::npos)
      << fvv_decoder_error(dec.get());
  FramePtr ok = DecodeFrame(dec.get(), 0, nullptr);
  EXPECT_TRUE(ok);
  std::remove(path.c_str());
}

}  // namespace
}  // namespace fvv

namespace fvv {
namespace {

// A stream with the texture in chunks (format version 11), in memory and as a file.
struct RangesFixture {
  std::vector<uint8_t> bytes;
  std::string path;
};

RangesFixture ChunkedStream(bool fast_start, const std::string& name) {
  SampleStreamOptions o = Options();
  o.coder = EntropyCoder::kQuadtree;
  o.texture_chunks = true;
  o.fast_start = fast_start;
  o.bpp = 3.0;
  auto s = MakeSampleStream(o);
  EXPECT_TRUE(s.ok());
  RangesFixture fx;
  fx.bytes = *WriteStreamToMemory(s->info, s->fragments);
  fx.path = ::testing::TempDir() + "/" + name;
  FILE* f = std::fopen(fx.path.c_str(), "wb");
  EXPECT_NE(f, nullptr);
  EXPECT_EQ(std::fwrite(fx.bytes.data(), 1, fx.bytes.size(), f), fx.bytes.size());
  std::fclose(f);
  return fx;
}

// Adds what the decoder asks for, at most 64 bytes of it at a time (a client
// may fetch less or more), until it is ready; the number of requests.
int FetchHead(fvv_decoder* dec, const std::vector<uint8_t>& bytes) {
  int requests = 0;
  for (;;) {
    fvv_event event;
    EXPECT_EQ(fvv_decoder_process(dec, &event), FVV_OK) << fvv_decoder_error(dec);
    if (event != FVV_EVENT_NEED_MORE_INPUT) {
      EXPECT_EQ(event, FVV_EVENT_READY);
      return requests;
    }
    uint64_t offset = 0, size = 0;
    EXPECT_EQ(fvv_decoder_wanted_range(dec, &offset, &size), 1);
    EXPECT_LE(offset + size, bytes.size());
    size = std::min<uint64_t>(size, 64);
    EXPECT_EQ(fvv_decoder_add_range(dec, offset, bytes.data() + offset, size_t(size)), FVV_OK);
    if (++requests > 1000) {
      ADD_FAILURE() << "the head never completes";
      return requests;
    }
  }
}

void ExpectSameViews(const fvv_frame& a, const fvv_frame& b, const char* what) {
  ASSERT_EQ(a.camera_count, b.camera_count);
  const size_t n = size_t{a.width} * a.height * 3;
  for (uint32_t c = 0; c < a.camera_count; ++c) {
    ASSERT_EQ(a.views[c].pixels == nullptr, b.views[c].pixels == nullptr) << what;
    if (a.views[c].pixels) {
      EXPECT_EQ(std::memcmp(a.views[c].pixels, b.views[c].pixels, n), 0)
          << what << ", camera " << c;
    }
  }
}

TEST(DecoderRanges, FragmentsFetchedAsPrefixesDecodeAsTheFileAtThatBudget) {
  const RangesFixture fx = ChunkedStream(/*fast_start=*/false, "fvv_ranges_index_end.fvv");
  DecoderPtr dec = MakeDecoder();
  ASSERT_EQ(fvv_decoder_open_ranges(dec.get(), fx.bytes.size()), FVV_OK);
  // Only what it asks for: the header boxes, then the index at the end.
  const int requests = FetchHead(dec.get(), fx.bytes);
  EXPECT_GE(requests, 2);
  fvv_stream_info info;
  ASSERT_EQ(fvv_decoder_get_info(dec.get(), &info), FVV_OK);
  EXPECT_EQ(info.format_version, 11u);
  ASSERT_EQ(fvv_decoder_fragment_count(dec.get()), 6u);  // 3 spans x 2 camera groups
  std::vector<fvv_fragment_info> frags(6);
  uint64_t head = 0;
  for (uint32_t i = 0; i < 6; ++i) {
    ASSERT_EQ(fvv_decoder_get_fragment(dec.get(), i, &frags[i]), FVV_OK);
    EXPECT_LT(frags[i].held, frags[i].head_size);  // at most the box header the head walk read
    EXPECT_LT(frags[i].head_size, frags[i].size);
    head = std::max(head, frags[i].head_size);
  }
  fvv_status status;
  EXPECT_EQ(frags[2].held, 0u);
  EXPECT_EQ(DecodeFrame(dec.get(), 5, nullptr, &status), nullptr);
  EXPECT_EQ(status, FVV_INVALID_ARGUMENT);  // nothing of span 1 fetched yet
  // A prefix that ends inside the head.
  ASSERT_EQ(fvv_decoder_add_range(dec.get(), frags[0].offset, fx.bytes.data() + frags[0].offset,
                                  size_t(frags[0].head_size - 1)),
            FVV_OK);
  ASSERT_EQ(fvv_decoder_add_range(dec.get(), frags[1].offset, fx.bytes.data() + frags[1].offset,
                                  size_t(frags[1].head_size + 40)),
            FVV_OK);
  EXPECT_EQ(DecodeFrame(dec.get(), 0, nullptr, &status), nullptr);
  EXPECT_EQ(status, FVV_TRUNCATED);

  DecoderPtr file = MakeDecoder();
  ASSERT_EQ(fvv_decoder_open_file(file.get(), fx.path.c_str()), FVV_OK);
  // The same prefix of each fragment of span 0, then all of them.
  for (const uint64_t prefix : {head + 200, head + 900, uint64_t{0}}) {
    for (uint32_t i : {0u, 1u}) {
      const uint64_t n = prefix == 0 ? frags[i].size : std::min(prefix, frags[i].size);
      ASSERT_EQ(fvv_decoder_add_range(dec.get(), frags[i].offset, fx.bytes.data() + frags[i].offset,
                                      size_t(n)),
                FVV_OK);
    }
    fvv_fragment_info held;
    ASSERT_EQ(fvv_decoder_get_fragment(dec.get(), 0, &held), FVV_OK);
    EXPECT_EQ(held.held, prefix == 0 ? frags[0].size : std::min(prefix, frags[0].size));
    FramePtr got = DecodeFrame(dec.get(), 2, nullptr, &status);
    ASSERT_NE(got, nullptr) << fvv_decoder_error(dec.get());
    fvv_decode_budget budget{};
    budget.max_bytes_per_gop = prefix;
    FramePtr want = DecodeFrame(file.get(), 2, &budget, &status);
    ASSERT_NE(want, nullptr) << fvv_decoder_error(file.get());
    ExpectSameViews(*got, *want, prefix == 0 ? "whole" : "prefix");
    EXPECT_EQ(got->report.bytes_decoded, want->report.bytes_decoded);
    EXPECT_EQ(got->report.complete, prefix == 0);
  }
  // Span 1 with only camera group 0 fetched: camera 0 alone decodes.
  ASSERT_EQ(fvv_decoder_add_range(dec.get(), frags[2].offset, fx.bytes.data() + frags[2].offset,
                                  size_t(frags[2].size)),
            FVV_OK);
  fvv_decode_budget only0{};
  only0.camera_mask = 1;
  FramePtr one = DecodeFrame(dec.get(), 5, &only0, &status);
  ASSERT_NE(one, nullptr) << fvv_decoder_error(dec.get());
  EXPECT_NE(one->views[0].pixels, nullptr);
  EXPECT_EQ(one->views[2].pixels, nullptr);
  EXPECT_EQ(DecodeFrame(dec.get(), 5, nullptr, &status), nullptr);
  EXPECT_EQ(status, FVV_INVALID_ARGUMENT);
}

TEST(DecoderRanges, ADamagedChunkAndAStreamWithoutIndexAreReported) {
  RangesFixture fx = ChunkedStream(/*fast_start=*/true, "fvv_ranges_front.fvv");
  {
    DecoderPtr dec = MakeDecoder();
    ASSERT_EQ(fvv_decoder_open_ranges(dec.get(), fx.bytes.size()), FVV_OK);
    FetchHead(dec.get(), fx.bytes);
    fvv_fragment_info f;
    ASSERT_EQ(fvv_decoder_get_fragment(dec.get(), 0, &f), FVV_OK);
    std::vector<uint8_t> damaged(fx.bytes.begin() + f.offset, fx.bytes.begin() + f.offset + f.size);
    damaged.back() ^= 1;  // the last chunk's data
    ASSERT_EQ(fvv_decoder_add_range(dec.get(), f.offset, damaged.data(), damaged.size() - 1),
              FVV_OK);
    fvv_decode_budget only0{};
    only0.camera_mask = 1;
    fvv_status status;
    EXPECT_NE(DecodeFrame(dec.get(), 0, &only0, &status), nullptr);  // the damage is not held yet
    ASSERT_EQ(fvv_decoder_add_range(dec.get(), f.offset, damaged.data(), damaged.size()), FVV_OK);
    EXPECT_EQ(DecodeFrame(dec.get(), 0, &only0, &status), nullptr);
    EXPECT_EQ(status, FVV_CHECKSUM_MISMATCH);
    EXPECT_EQ(fvv_decoder_add_range(dec.get(), fx.bytes.size(), fx.bytes.data(), 1),
              FVV_INVALID_ARGUMENT);  // past the end
  }
  // Without an index the fragments cannot be found by ranges.
  {
    SampleStreamOptions o = Options();
    o.fast_start = false;
    auto s = MakeSampleStream(o);
    ASSERT_TRUE(s.ok());
    std::vector<uint8_t> bytes = *WriteStreamToMemory(s->info, s->fragments);
    uint64_t index_offset = 0;
    for (int k = 7; k >= 0; --k)
      index_offset = (index_offset << 8) | bytes[kHeaderIndexOffsetPos + k];
    bytes.resize(size_t(index_offset));
    for (int k = 0; k < 8; ++k) bytes[kHeaderIndexOffsetPos + k] = 0;
    DecoderPtr dec = MakeDecoder();
    ASSERT_EQ(fvv_decoder_open_ranges(dec.get(), bytes.size()), FVV_OK);
    ASSERT_EQ(fvv_decoder_add_range(dec.get(), 0, bytes.data(), bytes.size()), FVV_OK);
    fvv_event event;
    EXPECT_EQ(fvv_decoder_process(dec.get(), &event), FVV_UNSUPPORTED);
    EXPECT_NE(std::string(fvv_decoder_error(dec.get())).find("no index"), std::string::npos)
        << fvv_decoder_error(dec.get());
  }
}

}  // namespace
}  // namespace fvv

namespace fvv {
namespace {

// A decoder's claim by limits (SPEC.md 5.1): a stream whose level is high for
// its camera count alone decodes under a claim of level 2's memory; one whose
// GOPs or fragments exceed the claim is LimitExceeded from every input, before
// anything it sizes is allocated.
TEST(DecoderClaim, LimitsOnGopSamplesAndFragmentBytesAreTheStreamsOwn) {
  fvv_decoder_settings claim;
  fvv_decoder_default_settings(&claim);
  EXPECT_EQ(claim.max_gop_samples, 0u);
  EXPECT_EQ(claim.max_fragment_bytes, 0u);
  claim.max_gop_samples = uint64_t{1} << 26;
  claim.max_fragment_bytes = uint64_t{32} << 20;
  // 31 cameras: level 3 for its camera count; GOPs of 4 frames x 1 camera x 32x24.
  SampleStreamOptions o = Options();
  o.cameras = 31;
  o.gop_cameras = 1;
  o.level = 3;
  const std::string studio = WriteSampleStreamFile(o, "fvv_claim_31_cameras.fvv");
  {
    DecoderPtr dec = MakeDecoder(&claim);
    ASSERT_EQ(fvv_decoder_open_file(dec.get(), studio.c_str()), FVV_OK)
        << fvv_decoder_error(dec.get());
    fvv_stream_info info;
    ASSERT_EQ(fvv_decoder_get_info(dec.get(), &info), FVV_OK);
    EXPECT_EQ(info.level, 3u);
    fvv_status status;
    EXPECT_NE(DecodeFrame(dec.get(), 5, nullptr, &status), nullptr) << fvv_decoder_error(dec.get());
  }
  // GOPs of 4 frames x 2 cameras x 32x24 = 6144 samples, against a claim of 6000.
  const Fixture& fx = Shared();
  claim.max_gop_samples = 6000;
  {
    DecoderPtr dec = MakeDecoder(&claim);
    EXPECT_EQ(fvv_decoder_open_file(dec.get(), fx.path.c_str()), FVV_LIMIT_EXCEEDED);
    EXPECT_NE(std::string(fvv_decoder_error(dec.get())).find("this decoder holds"),
              std::string::npos)
        << fvv_decoder_error(dec.get());
  }
  {
    DecoderPtr dec = MakeDecoder(&claim);
    ASSERT_EQ(fvv_decoder_push(dec.get(), fx.bytes.data(), fx.bytes.size()), FVV_OK);
    fvv_event event = FVV_EVENT_NEED_MORE_INPUT;
    EXPECT_EQ(fvv_decoder_process(dec.get(), &event), FVV_LIMIT_EXCEEDED);
  }
  {
    DecoderPtr dec = MakeDecoder(&claim);
    ASSERT_EQ(fvv_decoder_open_ranges(dec.get(), fx.bytes.size()), FVV_OK);
    ASSERT_EQ(fvv_decoder_add_range(dec.get(), 0, fx.bytes.data(), fx.bytes.size()), FVV_OK);
    fvv_event event;
    EXPECT_EQ(fvv_decoder_process(dec.get(), &event), FVV_LIMIT_EXCEEDED);
  }
  // Fragments larger than the claim: the file opens, the frame does not decode.
  claim.max_gop_samples = 6144;
  claim.max_fragment_bytes = 100;
  {
    DecoderPtr dec = MakeDecoder(&claim);
    ASSERT_EQ(fvv_decoder_open_file(dec.get(), fx.path.c_str()), FVV_OK);
    fvv_status status;
    EXPECT_EQ(DecodeFrame(dec.get(), 0, nullptr, &status), nullptr);
    EXPECT_EQ(status, FVV_LIMIT_EXCEEDED);
  }
  {
    DecoderPtr dec = MakeDecoder(&claim);
    ASSERT_EQ(fvv_decoder_push(dec.get(), fx.bytes.data(), fx.bytes.size()), FVV_OK);
    fvv_status s = FVV_OK;
    for (int i = 0; i < 100 && s == FVV_OK; ++i) {
      fvv_event event;
      s = fvv_decoder_process(dec.get(), &event);
      if (s == FVV_OK && event == FVV_EVENT_NEED_MORE_INPUT) break;
    }
    EXPECT_EQ(s, FVV_LIMIT_EXCEEDED);
  }
}

}  // namespace
}  // namespace fvv
