// The surface of every frame (SPEC.md 3.5.2): its values code and decode
// exactly, damaged or out-of-range values are Corrupt, a fragment carries it in
// channel 3's chunks right after its head, a prefix that ends before its last
// chunk leaves it out (the frames keep the model's positions), and the C API
// hands each frame's bind-pose positions out.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "conformance/sample/sample_stream.h"
#include "container/file_reader.h"
#include "container/fragment.h"
#include "container/surface_displacement.h"
#include "container/writer.h"
#include "container/zstd_frame.h"
#include "fvv/fvv_decoder.h"
#include "player/decoder/gop_decoder.h"

namespace fvv {
namespace {

TEST(SurfaceValues, DecodeToWhatWasCoded) {
  std::mt19937 rng(7);
  const uint32_t frames = 3, vertices = 500;
  std::vector<int32_t> values(frames * vertices);
  std::uniform_int_distribution<int32_t> small(-40, 40), large(-kMaxSurfaceValue, kMaxSurfaceValue);
  for (size_t i = 0; i < values.size(); ++i) values[i] = i % 50 == 0 ? large(rng) : small(rng);
  values[1] = kMaxSurfaceValue, values[2] = -kMaxSurfaceValue;  // the widest residual
  const std::vector<uint8_t> coded = EncodeSurfaceDisplacements(values, frames, vertices);
  std::vector<int32_t> back;
  ASSERT_TRUE(DecodeSurfaceDisplacements(coded.data(), coded.size(), frames, vertices, &back).ok());
  EXPECT_EQ(back, values);
  // The same bytes read as another shape do not fit.
  EXPECT_EQ(
      DecodeSurfaceDisplacements(coded.data(), coded.size(), frames, vertices + 1, &back).code(),
      StatusCode::kCorrupt);
}

// A zstd frame of the given residual bytes, as a writer that does not hold to
// the rules would make it.
std::vector<uint8_t> Frame(const std::vector<uint8_t>& content) {
  return ZstdCompress(content.data(), content.size(), 3);
}

TEST(SurfaceValues, BadContentIsCorrupt) {
  std::vector<int32_t> out;
  const auto decode = [&](const std::vector<uint8_t>& coded, uint32_t frames, uint32_t vertices) {
    return DecodeSurfaceDisplacements(coded.data(), coded.size(), frames, vertices, &out).code();
  };
  // Two values, one byte each: fine.
  EXPECT_EQ(decode(Frame({2, 3}), 1, 2), StatusCode::kOk);
  EXPECT_EQ(out, (std::vector<int32_t>{1, -1}));
  // A byte after the last residual; a residual cut by the content's end.
  EXPECT_EQ(decode(Frame({2, 3, 0}), 1, 2), StatusCode::kCorrupt);
  EXPECT_EQ(decode(Frame({2, 0x83}), 1, 2), StatusCode::kCorrupt);
  // A six-byte residual; one of 2^32.
  EXPECT_EQ(decode(Frame({0x80, 0x80, 0x80, 0x80, 0x80, 0x00}), 1, 1), StatusCode::kCorrupt);
  EXPECT_EQ(decode(Frame({0x80, 0x80, 0x80, 0x80, 0x10}), 1, 1), StatusCode::kCorrupt);
  // 2^20 steps (zigzag 2^21), and 2^20 reached by prediction from the frame before.
  EXPECT_EQ(decode(Frame({0x80, 0x80, 0x80, 0x01}), 1, 1), StatusCode::kCorrupt);
  EXPECT_EQ(decode(Frame({0xFE, 0xFF, 0x7F, 2}), 2, 1), StatusCode::kCorrupt);
  // More content than five bytes a value may declare: refused before it is allocated.
  EXPECT_EQ(decode(Frame(std::vector<uint8_t>(11, 0)), 1, 2), StatusCode::kCorrupt);
  // Not a zstd frame at all.
  EXPECT_EQ(decode({1, 2, 3, 4, 5, 6, 7, 8}, 1, 2), StatusCode::kCorrupt);
}

TEST(SurfaceValues, PositionsAreTheModelsMovedAlongItsNormals) {
  Mesh mesh;
  mesh.positions = {{0.1f, 1.25f, -0.3f}, {0.7f, 0.2f, 0.05f}};
  mesh.normals = {{0.0f, 1.0f, 0.0f}, {0.6f, 0.0f, 0.8f}};
  const std::vector<int32_t> values = {256, -3};
  std::vector<float> p;
  SurfacePositions(mesh, values.data(), 8, &p);  // steps of 2^-8 m
  ASSERT_EQ(p.size(), 6u);
  EXPECT_EQ(p[1], 2.25f);  // 256 steps = 1 m along +y
  EXPECT_EQ(p[0], 0.1f);
  for (int k = 0; k < 3; ++k) {
    const double want = double(mesh.positions[1][k]) + (-3.0 / 256) * double(mesh.normals[1][k]);
    EXPECT_EQ(p[3 + k], float(want));
  }
}

SampleStreamOptions SurfaceOptions() {
  SampleStreamOptions o;
  o.frames = 6;
  o.cameras = 2;
  o.atlas_width = 48;
  o.atlas_height = 48;
  o.gop_frames = 4;
  o.gop_cameras = 1;
  o.coder = EntropyCoder::kQuadtree;
  o.bpp = 2.0;
  o.texture_chunks = true;
  o.surface = true;
  return o;
}

TEST(SurfaceFragment, RidesInGroupZerosChunksFirstAndAPrefixTakesItOrLeavesIt) {
  auto sample = MakeSampleStream(SurfaceOptions());
  ASSERT_TRUE(sample.ok()) << sample.status().ToString();
  const std::vector<uint8_t> bytes = *WriteStreamToMemory(sample->info, sample->fragments);
  MemorySource source(bytes.data(), bytes.size());
  auto reader = FileReader::Open(&source);
  ASSERT_TRUE(reader.ok()) << reader.status().ToString();
  const StreamInfo& info = (*reader)->info();
  EXPECT_EQ(info.header.format_version, 12);
  const uint32_t nv = uint32_t(info.model.mesh.positions.size());
  ASSERT_EQ((*reader)->fragment_count(), 4u);  // 2 spans x 2 camera groups
  for (size_t span = 0; span < 2; ++span) {
    auto first = (*reader)->ReadFragment(2 * span);
    auto second = (*reader)->ReadFragment(2 * span + 1);
    ASSERT_TRUE(first.ok() && second.ok());
    ASSERT_TRUE(first->has_surface);
    EXPECT_FALSE(second->has_surface);
    EXPECT_EQ(first->surface, sample->fragments[2 * span].surface);
    // Channel 3 first: the head plus the surface's chunks is the shortest
    // prefix that holds it.
    ASSERT_FALSE(first->chunks.empty());
    EXPECT_EQ(first->chunks[0].channel, kSurfaceChannel);
    uint64_t surface_end = first->head_bytes;
    for (const TextureChunk& c : first->chunks) {
      if (c.channel != kSurfaceChannel) break;
      surface_end += kChunkHeaderBytes + c.size;
    }
    EXPECT_TRUE(PrefixHoldsSurface(*first, 0));
    EXPECT_TRUE(PrefixHoldsSurface(*first, surface_end));
    EXPECT_FALSE(PrefixHoldsSurface(*first, surface_end - 1));
    EXPECT_FALSE(PrefixHoldsSurface(*first, first->head_bytes));
    EXPECT_FALSE(PrefixHoldsSurface(*second, 0));

    // Decoded whole: every frame's positions; from a prefix before its last
    // chunk: none, and the texture is still there.
    const std::vector<FragmentData> fragments = {*first, *second};
    GopBudget whole;
    auto gop = DecodeGop(info, fragments, whole, SerialRunner);
    ASSERT_TRUE(gop.ok()) << gop.status().ToString();
    ASSERT_EQ((*gop)->surface.size(), first->info.frame_count);
    std::vector<int32_t> values;
    ASSERT_TRUE(DecodeSurfaceDisplacements(first->surface.data(), first->surface.size(),
                                           first->info.frame_count, nv, &values)
                    .ok());
    for (uint32_t t = 0; t < first->info.frame_count; ++t) {
      std::vector<float> want;
      SurfacePositions(info.model.mesh, values.data() + size_t(t) * nv, 10, &want);
      EXPECT_EQ((*gop)->surface[t], want) << "frame " << t;
    }
    GopBudget cut;
    cut.max_bytes = surface_end - 1;
    gop = DecodeGop(info, fragments, cut, SerialRunner);
    ASSERT_TRUE(gop.ok()) << gop.status().ToString();
    EXPECT_TRUE((*gop)->surface.empty());
  }
}

TEST(SurfaceFragment, TheCApiHandsOutEachFramesSurfaceOrNull) {
  auto sample = MakeSampleStream(SurfaceOptions());
  ASSERT_TRUE(sample.ok());
  const std::vector<uint8_t> bytes = *WriteStreamToMemory(sample->info, sample->fragments);
  const std::string path = ::testing::TempDir() + "/surface_c_api.fvv";
  FILE* f = std::fopen(path.c_str(), "wb");
  ASSERT_TRUE(f);
  ASSERT_EQ(std::fwrite(bytes.data(), 1, bytes.size(), f), bytes.size());
  std::fclose(f);
  fvv_decoder* d = nullptr;
  ASSERT_EQ(fvv_decoder_create(nullptr, &d), FVV_OK);
  ASSERT_EQ(fvv_decoder_open_file(d, path.c_str()), FVV_OK);
  fvv_model model;
  ASSERT_EQ(fvv_decoder_get_model(d, &model), FVV_OK);
  // The surface's bytes past the head are known once a fragment was read.
  const auto surface_size = [&](uint32_t i) {
    fvv_fragment_info fi{};
    EXPECT_EQ(fvv_decoder_get_fragment(d, i, &fi), FVV_OK);
    return fi.surface_size;
  };
  uint32_t holding = UINT32_MAX;  // camera group 0's fragment of frame 5
  for (uint32_t i = 0; i < fvv_decoder_fragment_count(d); ++i) {
    fvv_fragment_info fi{};
    ASSERT_EQ(fvv_decoder_get_fragment(d, i, &fi), FVV_OK);
    EXPECT_EQ(fi.surface_size, 0u) << "fragment " << i << " was not read yet";
    if (fi.first_camera == 0 && fi.first_frame <= 5 && 5 < fi.first_frame + fi.frame_count) {
      holding = i;
    }
  }
  ASSERT_LT(holding, sample->fragments.size());
  fvv_frame* frame = nullptr;
  ASSERT_EQ(fvv_decoder_decode_frame(d, 5, nullptr, &frame), FVV_OK);
  ASSERT_NE(frame->surface, nullptr);
  const uint64_t data = sample->fragments[holding].surface.size();
  ASSERT_GT(data, 0u);
  EXPECT_EQ(surface_size(holding), data + (data + 65534) / 65535 * kChunkHeaderBytes);
  for (uint32_t i = 0; i < fvv_decoder_fragment_count(d); ++i) {
    if (i != holding) {
      EXPECT_EQ(surface_size(i), 0u) << "fragment " << i;
    }
  }
  // Some vertex moved, none by more than the sample's swing of 300 mm.
  double largest = 0;
  for (uint32_t v = 0; v < model.vertex_count; ++v) {
    double d2 = 0;
    for (int k = 0; k < 3; ++k) {
      d2 += std::pow(double(frame->surface[3 * v + k]) - model.positions[3 * v + k], 2);
    }
    largest = std::max(largest, std::sqrt(d2));
  }
  EXPECT_GT(largest, 0.01);
  EXPECT_LT(largest, 0.3);
  fvv_frame_release(frame);
  // A budget of the longest head (the surface's chunks follow it): the
  // model's positions (NULL).
  fvv_decode_budget budget{};
  for (uint32_t i = 0; i < fvv_decoder_fragment_count(d); ++i) {
    fvv_fragment_info fi;
    ASSERT_EQ(fvv_decoder_get_fragment(d, i, &fi), FVV_OK);
    budget.max_bytes_per_gop = std::max(budget.max_bytes_per_gop, fi.head_size);
  }
  ASSERT_EQ(fvv_decoder_decode_frame(d, 5, &budget, &frame), FVV_OK);
  EXPECT_EQ(frame->surface, nullptr);
  fvv_frame_release(frame);
  fvv_decoder_destroy(d);
}

}  // namespace
}  // namespace fvv
