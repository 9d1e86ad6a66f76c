// The body model's writer (SPEC.md 3.3, 3.3.1): the encoder's half of
// body_model.cc, apart so that the decoder library needs no zstd compressor.
#include <cstring>

#include "container/body_model.h"
#include "container/zstd_frame.h"

namespace fvv {
namespace {

// Floats and integers column-wise with their bytes split into planes (all
// first bytes, then all second bytes, ...), as body_model.cc reads them.
template <typename T>
void PutPlanes(const std::vector<T>& values, ByteWriter* w) {
  static_assert(sizeof(T) == 2 || sizeof(T) == 4, "16- or 32-bit values");
  std::vector<uint8_t> raw(values.size() * sizeof(T));
  for (size_t i = 0; i < values.size(); ++i) {
    uint8_t b[sizeof(T)];
    std::memcpy(b, &values[i], sizeof(T));  // little-endian hosts only (checked in CMake)
    for (size_t k = 0; k < sizeof(T); ++k) raw[k * values.size() + i] = b[k];
  }
  w->Bytes(raw);
}

template <typename T, size_t N>
std::vector<T> Column(const std::vector<std::array<T, N>>& v, size_t k) {
  std::vector<T> c(v.size());
  for (size_t i = 0; i < v.size(); ++i) c[i] = v[i][k];
  return c;
}

void PutSkeleton(const Skeleton& skeleton, ByteWriter* w) {
  w->U16(static_cast<uint32_t>(skeleton.bones.size()));
  for (const Bone& b : skeleton.bones) {
    w->Str(b.name);
    w->I16(b.parent);
    for (float v : b.rest_translation) w->F32(v);
    for (float v : b.rest_rotation) w->F32(v);
    w->U8(static_cast<uint8_t>(b.order));
    w->U8(b.dof_mask);
    for (int k = 0; k < kDofKinds; ++k) {
      if (b.dof_mask & (1u << k)) {
        w->F32(b.dof_min[k]);
        w->F32(b.dof_max[k]);
      }
    }
  }
}

// Triangle corners as differences from the same corner of the previous
// triangle (mod 2^32): neighbouring triangles share nearby vertices.
void PutTriangles(const std::vector<std::array<uint32_t, 3>>& triangles, ByteWriter* w) {
  for (size_t k = 0; k < 3; ++k) {
    std::vector<uint32_t> d(triangles.size());
    uint32_t prev = 0;
    for (size_t i = 0; i < triangles.size(); ++i) {
      d[i] = triangles[i][k] - prev;
      prev = triangles[i][k];
    }
    PutPlanes(d, w);
  }
}

uint32_t ZigZag(int64_t d) { return uint32_t((uint64_t(d) << 1) ^ uint64_t(d >> 63)); }
// A column of values on a grid of 2^-exponent, as differences from the
// previous vertex's value (zig-zag, so small steps either way have small codes).
std::vector<uint32_t> GridDeltas(const std::vector<float>& values, int exponent) {
  std::vector<uint32_t> d(values.size());
  int64_t prev = 0;
  for (size_t i = 0; i < values.size(); ++i) {
    const int64_t q = int64_t(GridSteps(values[i], exponent));
    d[i] = ZigZag(q - prev);
    prev = q;
  }
  return d;
}

std::vector<uint8_t> SerialiseModel(const BodyModel& model) {
  ByteWriter w;
  PutSkeleton(model.skeleton, &w);
  const Mesh& m = model.mesh;
  w.U32(static_cast<uint32_t>(m.positions.size()));
  w.U32(static_cast<uint32_t>(m.triangles.size()));
  for (size_t k = 0; k < 3; ++k) PutPlanes(Column(m.positions, k), &w);
  for (size_t k = 0; k < 3; ++k) PutPlanes(Column(m.normals, k), &w);
  for (size_t k = 0; k < 2; ++k) PutPlanes(Column(m.uvs, k), &w);
  for (size_t k = 0; k < kMaxInfluences; ++k) PutPlanes(Column(m.joints, k), &w);
  for (size_t k = 0; k < kMaxInfluences; ++k) PutPlanes(Column(m.weights, k), &w);
  w.Bytes(m.segments);
  PutTriangles(m.triangles, &w);
  return std::move(w.bytes());
}

// model_data of 'modl' version 1 (SPEC.md 3.3.1); the mesh taken to the grid's
// nearest values, which for a QuantiseModel'd mesh are its own.
std::vector<uint8_t> SerialiseQuantisedModel(const BodyModel& model) {
  const ModelQuantisation& q = model.quantisation;
  ByteWriter w;
  PutSkeleton(model.skeleton, &w);
  const Mesh& m = model.mesh;
  const size_t n = m.positions.size();
  w.U32(static_cast<uint32_t>(n));
  w.U32(static_cast<uint32_t>(m.triangles.size()));
  w.U8(q.position_exponent);
  w.U8(q.uv_exponent);
  w.U8(q.normal_bits);
  w.U8(q.weight_bits);
  for (size_t k = 0; k < 3; ++k)
    PutPlanes(GridDeltas(Column(m.positions, k), q.position_exponent), &w);
  std::vector<uint16_t> codes[2] = {std::vector<uint16_t>(n), std::vector<uint16_t>(n)};
  for (size_t i = 0; i < n; ++i) {
    const std::array<uint32_t, 2> c = EncodeOctahedralNormal(m.normals[i], q.normal_bits);
    codes[0][i] = uint16_t(c[0]);
    codes[1][i] = uint16_t(c[1]);
  }
  PutPlanes(codes[0], &w);
  PutPlanes(codes[1], &w);
  for (size_t k = 0; k < 2; ++k) PutPlanes(GridDeltas(Column(m.uvs, k), q.uv_exponent), &w);
  for (size_t k = 0; k < kMaxInfluences; ++k) PutPlanes(Column(m.joints, k), &w);
  std::vector<std::array<uint16_t, kMaxInfluences>> weights(n);
  for (size_t i = 0; i < n; ++i) {
    const std::array<uint32_t, 4> qw = QuantiseWeights(m.weights[i], q.weight_bits);
    for (int k = 0; k < kMaxInfluences; ++k) weights[i][k] = uint16_t(qw[k]);
  }
  for (size_t k = 0; k < kMaxInfluences; ++k) PutPlanes(Column(weights, k), &w);
  w.Bytes(m.segments);
  PutTriangles(m.triangles, &w);
  return std::move(w.bytes());
}

}  // namespace

std::vector<uint8_t> WriteModelBox(const BodyModel& model) {
  const bool quantised = model.quantisation.quantised;
  const std::vector<uint8_t> raw =
      quantised ? SerialiseQuantisedModel(model) : SerialiseModel(model);
  // The zstd frame carries its content checksum: damage to the model is detected.
  const std::vector<uint8_t> packed = ZstdCompress(raw.data(), raw.size(), 19);
  const size_t n = packed.size();
  ByteWriter w;
  if (n == 0 || n >= raw.size() + 4) {
    w.U8(kCompressionNone);
    w.U32(static_cast<uint32_t>(raw.size()));
    w.Bytes(raw);
  } else {
    w.U8(kCompressionZstd);
    w.U32(static_cast<uint32_t>(raw.size()));
    w.Bytes(packed.data(), n);
  }
  return MakeBox(box::kModel, quantised ? 1 : 0, kBoxFlagEssential, w.bytes());
}

}  // namespace fvv
