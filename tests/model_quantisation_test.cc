// The body model on a grid ('modl' version 1, SPEC.md 3.3.1): what it
// changes in the model, that a decoder gets exactly the encoder's snapped
// model, its size against floats, and the errors a damaged box gives.
#include "container/model_quantisation.h"

#include <gtest/gtest.h>
#include <zstd.h>

#include <cmath>
#include <cstring>
#include <random>

#include "container/body_model.h"
#include "encoder/atlas/atlas.h"
#include "encoder/body/generic_body.h"

namespace fvv {
namespace {

double AngleDegrees(const std::array<float, 3>& a, const std::array<float, 3>& b) {
  double dot = 0, na = 0, nb = 0;
  for (int k = 0; k < 3; ++k) {
    dot += double(a[k]) * b[k];
    na += double(a[k]) * a[k];
    nb += double(b[k]) * b[k];
  }
  return std::acos(std::min(1.0, dot / std::sqrt(na * nb))) * 180 / M_PI;
}

bool SameBits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// The model a player draws: the generic body with its atlas.
BodyModel AtlasBody(uint32_t atlas_side) {
  BodyModel m = MakeGenericBody();
  AtlasOptions ao;
  ao.size = atlas_side;
  StatusOr<Atlas> atlas = BuildAtlas(m.mesh, ao);
  EXPECT_TRUE(atlas.ok()) << atlas.status().ToString();
  m.mesh = std::move(atlas->mesh);
  return m;
}

StatusOr<BodyModel> RoundTrip(const std::vector<uint8_t>& box_bytes) {
  FVV_ASSIGN_OR_RETURN(const BoxHeader h,
                       ParseBoxHeader(box_bytes.data(), box_bytes.size(), 0, "test"));
  BodyModel out;
  FVV_RETURN_IF_ERROR(ReadModel(h, box_bytes.data() + h.header_size, AllLevels().back(), &out));
  return out;
}

TEST(ModelQuantisation, OctahedralNormalsAreUnitAndClose) {
  std::mt19937 rng(5);
  std::normal_distribution<float> g;
  for (int bits : {6, 10, 16}) {
    // The grid's cells are 2 / (2^bits - 1) wide in the octahedron's plane;
    // the nearest code is at most about 1.5 times as far in radians.
    const double bound = 1.5 * 180 / M_PI * 2.0 / ((1 << bits) - 1);
    double worst = 0;
    for (int i = 0; i < 20000; ++i) {
      const std::array<float, 3> n = {g(rng), g(rng), g(rng)};
      const std::array<uint32_t, 2> c = EncodeOctahedralNormal(n, bits);
      ASSERT_LT(c[0], 1u << bits);
      ASSERT_LT(c[1], 1u << bits);
      const std::array<float, 3> d = DecodeOctahedralNormal(c[0], c[1], bits);
      EXPECT_NEAR(double(d[0]) * d[0] + double(d[1]) * d[1] + double(d[2]) * d[2], 1.0, 1e-6);
      worst = std::max(worst, AngleDegrees(n, d));
    }
    EXPECT_LT(worst, bound) << bits << " bits";
    EXPECT_GT(worst, bound / 20) << bits << " bits: the test's normals do not exercise the grid";
  }
  // A decoded normal codes to itself (or to a code with the same decoded
  // floats, where the octahedron's border folds two codes onto one normal).
  const int bits = 7;
  for (uint32_t u = 0; u < (1u << bits); ++u) {
    for (uint32_t v = 0; v < (1u << bits); ++v) {
      const std::array<float, 3> d = DecodeOctahedralNormal(u, v, bits);
      const std::array<uint32_t, 2> c = EncodeOctahedralNormal(d, bits);
      const std::array<float, 3> e = DecodeOctahedralNormal(c[0], c[1], bits);
      for (int k = 0; k < 3; ++k) ASSERT_TRUE(SameBits(d[k], e[k])) << u << ", " << v;
    }
  }
  // Directions along the axes decode exactly.
  const std::array<float, 3> up = DecodeOctahedralNormal(511, 511, 10);  // X = Y = -1 of 1023
  EXPECT_NEAR(up[2], 1.0f, 1e-5);
}

TEST(ModelQuantisation, WeightsKeepTheirSumByLargestRemainder) {
  const std::array<uint16_t, 4> w = {30000, 30000, 5535, 0};
  const std::array<uint32_t, 4> q = QuantiseWeights(w, 8);
  EXPECT_EQ(q[0] + q[1] + q[2] + q[3], 255u);
  EXPECT_EQ(q[3], 0u);  // a weight of nothing stays nothing
  for (int k = 0; k < 4; ++k) EXPECT_LE(std::fabs(q[k] * 257.0 - w[k]), 257.0) << k;
  const std::array<uint16_t, 4> whole = {65535, 0, 0, 0};
  EXPECT_EQ(QuantiseWeights(whole, 8), (std::array<uint32_t, 4>{255, 0, 0, 0}));
  EXPECT_EQ(QuantiseWeights(w, 16), (std::array<uint32_t, 4>{30000, 30000, 5535, 0}));
}

TEST(ModelQuantisation, DecoderGetsExactlyTheSnappedModelAtLessThanHalfTheBytes) {
  const BodyModel source = AtlasBody(512);
  BodyModel snapped = source;
  const ModelQuantisation grid = DefaultModelQuantisation(512);
  EXPECT_EQ(grid.uv_exponent, 15);  // 1/64 texel of 512
  ASSERT_TRUE(QuantiseModel(grid, &snapped).ok());
  const Mesh& a = source.mesh;
  const Mesh& b = snapped.mesh;
  ASSERT_EQ(a.positions.size(), b.positions.size());
  double worst_position = 0, worst_uv = 0, worst_normal = 0, worst_weight = 0;
  size_t moved = 0;
  for (size_t i = 0; i < a.positions.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      worst_position = std::max(worst_position,
                                std::fabs(double(a.positions[i][k]) - double(b.positions[i][k])));
      moved += a.positions[i][k] != b.positions[i][k];
    }
    for (int k = 0; k < 2; ++k) {
      worst_uv = std::max(worst_uv, std::fabs(double(a.uvs[i][k]) - double(b.uvs[i][k])));
    }
    worst_normal = std::max(worst_normal, AngleDegrees(a.normals[i], b.normals[i]));
    for (int k = 0; k < 4; ++k) {
      worst_weight = std::max(worst_weight, std::fabs(double(a.weights[i][k]) - b.weights[i][k]));
    }
  }
  EXPECT_GT(moved, a.positions.size());                      // the grid did something
  EXPECT_LE(worst_position, std::ldexp(1.0, -14) * 1.0001);  // half a step of 2^-13 m
  EXPECT_LE(worst_uv, std::ldexp(1.0, -16) * 1.0001);
  EXPECT_LT(worst_normal, 0.17);       // 10 bits
  EXPECT_LE(worst_weight, 3 * 257.0);  // a unit of 1/255 per influence, at most 3 moved up
  EXPECT_EQ(a.joints, b.joints);
  EXPECT_EQ(a.segments, b.segments);
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_TRUE(ValidateBodyModel(snapped, nullptr).ok());

  const std::vector<uint8_t> box = WriteModelBox(snapped);
  const std::vector<uint8_t> floats = WriteModelBox(source);
  StatusOr<BodyModel> decoded = RoundTrip(box);
  ASSERT_TRUE(decoded.ok()) << decoded.status().ToString();
  EXPECT_TRUE(decoded->quantisation == grid);
  for (size_t i = 0; i < b.positions.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      ASSERT_TRUE(SameBits(decoded->mesh.positions[i][k], b.positions[i][k])) << i;
      ASSERT_TRUE(SameBits(decoded->mesh.normals[i][k], b.normals[i][k])) << i;
    }
    for (int k = 0; k < 2; ++k) ASSERT_TRUE(SameBits(decoded->mesh.uvs[i][k], b.uvs[i][k])) << i;
  }
  EXPECT_EQ(decoded->mesh.weights, b.weights);
  EXPECT_EQ(decoded->mesh.joints, b.joints);
  EXPECT_EQ(decoded->mesh.triangles, b.triangles);
  // Snapping again changes nothing, and the decoded model writes the same box.
  BodyModel again = snapped;
  ASSERT_TRUE(QuantiseModel(grid, &again).ok());
  EXPECT_EQ(WriteModelBox(again), box);
  EXPECT_EQ(WriteModelBox(*decoded), box);
  // A float model still writes version 0 and reads back as floats.
  StatusOr<BodyModel> float_decoded = RoundTrip(floats);
  ASSERT_TRUE(float_decoded.ok()) << float_decoded.status().ToString();
  EXPECT_FALSE(float_decoded->quantisation.quantised);
  EXPECT_EQ(float_decoded->mesh.positions, a.positions);
  EXPECT_LT(box.size() * 2, floats.size()) << box.size() << " against " << floats.size();
  std::printf("modl: floats %zu bytes, on the grid %zu (%.1f %%)\n", floats.size(), box.size(),
              100.0 * double(box.size()) / double(floats.size()));
}

TEST(ModelQuantisation, ValuesBeyondTheGridAreRefused) {
  BodyModel m = AtlasBody(256);
  m.mesh.positions[3][1] = 5000.0f;  // 2^24 steps of 2^-13 m are 2048 m
  EXPECT_EQ(QuantiseModel(DefaultModelQuantisation(256), &m).code(), StatusCode::kInvalidArgument);
  ModelQuantisation bad = DefaultModelQuantisation(256);
  bad.weight_bits = 3;  // 7 does not divide 65535
  BodyModel n = AtlasBody(256);
  EXPECT_EQ(QuantiseModel(bad, &n).code(), StatusCode::kInvalidArgument);
}

std::vector<uint8_t> BoxAround(const std::vector<uint8_t>& raw, uint8_t version) {
  ByteWriter w;
  w.U8(0);  // stored uncompressed
  w.U32(uint32_t(raw.size()));
  w.Bytes(raw);
  return MakeBox(box::kModel, version, kBoxFlagEssential, w.bytes());
}

TEST(ModelQuantisation, DamagedGridDataIsCorrupt) {
  BodyModel m = AtlasBody(256);
  ASSERT_TRUE(QuantiseModel(DefaultModelQuantisation(256), &m).ok());
  const std::vector<uint8_t> box = WriteModelBox(m);
  StatusOr<BoxHeader> h = ParseBoxHeader(box.data(), box.size(), 0, "test");
  ASSERT_TRUE(h.ok());
  EXPECT_EQ(h->version, 1);
  const uint8_t* p = box.data() + h->header_size;
  ASSERT_EQ(p[0], 1);  // zstd
  std::vector<uint8_t> raw(size_t(p[1]) | size_t(p[2]) << 8 | size_t(p[3]) << 16 |
                           size_t(p[4]) << 24);
  ASSERT_EQ(ZSTD_decompress(raw.data(), raw.size(), p + 5, size_t(h->payload_size() - 5)),
            raw.size());
  // Version 1 after the skeleton: the counts, the grid's 4 bytes, positions
  // (3 x 4 byte planes), normals (2 x 2), uvs (2 x 4), joints (4 x 2),
  // weights (4 x 2), segments, triangles.
  const size_t n = m.mesh.positions.size();
  const size_t grid = raw.size() - (n * 41 + m.mesh.triangles.size() * 12) - 4;
  ASSERT_EQ(raw[grid + 0], 13);
  ASSERT_EQ(raw[grid + 2], 10);
  ASSERT_EQ(raw[grid + 3], 8);
  EXPECT_TRUE(RoundTrip(BoxAround(raw, 1)).ok());
  const size_t positions = grid + 4, normals = positions + 12 * n, weights = normals + 20 * n;
  struct Edit {
    const char* what;
    size_t at;
    uint8_t value;
    bool exclusive_or;  // else set
  };
  for (const Edit& e :
       {Edit{"position exponent 31", grid + 0, 31, false},
        Edit{"uv exponent 40", grid + 1, 40, false}, Edit{"normal bits 1", grid + 2, 1, false},
        Edit{"normal bits 17", grid + 2, 17, false}, Edit{"weight bits 3", grid + 3, 3, false},
        Edit{"a normal code of 11 bits", normals + n, 0x04, true},
        Edit{"weights that do not sum to 255", weights, 0x01, true},
        Edit{"a position 2^30 steps out", positions + 3 * n, 0x80, true}}) {
    std::vector<uint8_t> edited = raw;
    edited[e.at] = e.exclusive_or ? uint8_t(edited[e.at] ^ e.value) : e.value;
    StatusOr<BodyModel> r = RoundTrip(BoxAround(edited, 1));
    EXPECT_EQ(r.status().code(), StatusCode::kCorrupt) << e.what << ": " << r.status().ToString();
  }
  // The same data as version 0 is the wrong size; version 2 is unknown.
  EXPECT_EQ(RoundTrip(BoxAround(raw, 0)).status().code(), StatusCode::kCorrupt);
  EXPECT_EQ(RoundTrip(BoxAround(raw, 2)).status().code(), StatusCode::kUnsupported);
}

}  // namespace
}  // namespace fvv
