#include "container/body_model.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "container/zstd_frame.h"

namespace fvv {

std::array<int, 3> RotationOrderAxes(RotationOrder order) {
  switch (order) {
    case RotationOrder::kXYZ:
      return {0, 1, 2};
    case RotationOrder::kXZY:
      return {0, 2, 1};
    case RotationOrder::kYXZ:
      return {1, 0, 2};
    case RotationOrder::kYZX:
      return {1, 2, 0};
    case RotationOrder::kZXY:
      return {2, 0, 1};
    case RotationOrder::kZYX:
      break;
  }
  return {2, 1, 0};
}

std::vector<DofRef> Skeleton::Dofs() const {
  std::vector<DofRef> dofs;
  for (size_t b = 0; b < bones.size(); ++b) {
    for (int k = 0; k < kDofKinds; ++k) {
      if (bones[b].dof_mask & (1u << k)) dofs.push_back({static_cast<uint16_t>(b), uint8_t(k)});
    }
  }
  return dofs;
}

namespace {

constexpr size_t kMaxBoneNameBytes = 255;
// Bytes per vertex of the mesh arrays: version 0 (positions, normals, uvs as
// f32, joints, weights, segment) and version 1 (positions and uvs as u32
// differences, normals as two u16 codes).
constexpr uint64_t kFloatVertexBytes = 12 + 12 + 8 + 8 + 8 + 1;
constexpr uint64_t kGridVertexBytes = 12 + 4 + 8 + 8 + 8 + 1;

// Floats and integers are stored column-wise with their bytes split into planes
// (all first bytes, then all second bytes, ...): similar bytes sit together, which
// roughly halves what zstd leaves of a mesh (body_model_enc.cc writes them).
template <typename T>
bool GetPlanes(ByteReader* r, size_t count, std::vector<T>* values) {
  const uint8_t* p = r->Bytes(count * sizeof(T));
  if (p == nullptr) return false;
  values->resize(count);
  for (size_t i = 0; i < count; ++i) {
    uint8_t b[sizeof(T)];
    for (size_t k = 0; k < sizeof(T); ++k) b[k] = p[k * count + i];
    std::memcpy(&(*values)[i], b, sizeof(T));
  }
  return true;
}

template <typename T, size_t N>
bool GetColumns(ByteReader* r, size_t count, std::vector<std::array<T, N>>* out) {
  out->resize(count);
  std::vector<T> c;
  for (size_t k = 0; k < N; ++k) {
    if (!GetPlanes(r, count, &c)) return false;
    for (size_t i = 0; i < count; ++i) (*out)[i][k] = c[i];
  }
  return true;
}

int64_t UnZigZag(uint32_t z) { return int64_t(z >> 1) ^ -int64_t(z & 1); }

// Upper bound of a raw model's size under `limits`: caps the allocation before
// decompression (version 1 stores less per vertex than version 0).
uint64_t MaxRawModelBytes(const LevelLimits& limits) {
  const uint64_t per_bone = 2 + kMaxBoneNameBytes + 2 + 28 + 2 + 48;
  const uint64_t per_vertex = kFloatVertexBytes;
  return 2 + limits.max_bones * per_bone + 8 + limits.max_vertices * per_vertex +
         uint64_t{limits.max_triangles} * 12;
}

Status ParseSkeleton(ByteReader* r, const LevelLimits& limits, const std::string& at,
                     Skeleton* skeleton) {
  const uint32_t bone_count = r->U16();
  if (bone_count > limits.max_bones) {
    return LimitExceeded(at + std::to_string(bone_count) + " bones (level allows " +
                         std::to_string(limits.max_bones) + ")");
  }
  auto& bones = skeleton->bones;
  bones.assign(bone_count, Bone());
  for (Bone& b : bones) {
    b.name = r->Str();
    b.parent = r->I16();
    for (float& v : b.rest_translation) v = r->F32();
    for (float& v : b.rest_rotation) v = r->F32();
    b.order = static_cast<RotationOrder>(r->U8());
    b.dof_mask = r->U8();
    for (int k = 0; k < kDofKinds; ++k) {
      if (b.dof_mask & (1u << k)) {
        b.dof_min[k] = r->F32();
        b.dof_max[k] = r->F32();
      }
    }
    if (r->overrun()) return Corrupt(at + "model data ends inside the skeleton");
  }
  return Status::Ok();
}

void GetTriangles(ByteReader* r, uint32_t count, std::vector<std::array<uint32_t, 3>>* triangles) {
  GetColumns(r, count, triangles);
  for (size_t k = 0; k < 3; ++k) {
    uint32_t prev = 0;
    for (auto& t : *triangles) {
      t[k] += prev;
      prev = t[k];
    }
  }
}

// Grid values from their zig-zag differences; false when one leaves the
// grid's range (|value| < 2^24, where its float is exact).
template <size_t N>
bool GetGridColumns(ByteReader* r, uint32_t count, int exponent,
                    std::vector<std::array<float, N>>* out) {
  out->resize(count);
  std::vector<uint32_t> d;
  for (size_t k = 0; k < N; ++k) {
    if (!GetPlanes(r, count, &d)) return false;
    int64_t value = 0;
    for (size_t i = 0; i < count; ++i) {
      value += UnZigZag(d[i]);
      if (value > kMaxQuantisedMagnitude || value < -kMaxQuantisedMagnitude) return false;
      (*out)[i][k] = GridFloat(value, exponent);
    }
  }
  return true;
}

Status ParseRawModel(const uint8_t* data, size_t size, const LevelLimits& limits,
                     const BoxHeader& box, BodyModel* model) {
  const std::string at = BoxContext(box);
  ByteReader r(data, size);
  FVV_RETURN_IF_ERROR(ParseSkeleton(&r, limits, at, &model->skeleton));
  const uint32_t vertex_count = r.U32();
  const uint32_t triangle_count = r.U32();
  if (vertex_count > limits.max_vertices || triangle_count > limits.max_triangles) {
    return LimitExceeded(at + std::to_string(vertex_count) + " vertices, " +
                         std::to_string(triangle_count) + " triangles (level allows " +
                         std::to_string(limits.max_vertices) + ", " +
                         std::to_string(limits.max_triangles) + ")");
  }
  const bool quantised = box.version == 1;
  ModelQuantisation& q = model->quantisation;
  q = ModelQuantisation();
  if (quantised) {
    q.quantised = true;
    q.position_exponent = r.U8();
    q.uv_exponent = r.U8();
    q.normal_bits = r.U8();
    q.weight_bits = r.U8();
    if (r.overrun()) return Corrupt(at + "model data ends before the quantisation grid");
    const Status grid = ValidateModelQuantisation(q);
    if (!grid.ok()) return Corrupt(at + grid.message());
  }
  // Exact size of what follows: checked before any array is allocated.
  const uint64_t per_vertex = quantised ? kGridVertexBytes : kFloatVertexBytes;
  const uint64_t need = uint64_t{vertex_count} * per_vertex + uint64_t{triangle_count} * 12;
  if (need != r.remaining()) {
    return Corrupt(at + "mesh arrays need " + std::to_string(need) + " bytes, model data has " +
                   std::to_string(r.remaining()));
  }
  Mesh& m = model->mesh;
  if (!quantised) {
    GetColumns(&r, vertex_count, &m.positions);
    GetColumns(&r, vertex_count, &m.normals);
    GetColumns(&r, vertex_count, &m.uvs);
  } else {
    if (!GetGridColumns(&r, vertex_count, q.position_exponent, &m.positions)) {
      return Corrupt(at + "a vertex position beyond 2^24 grid steps");
    }
    std::vector<std::array<uint16_t, 2>> codes;
    GetColumns(&r, vertex_count, &codes);
    const uint32_t max_code = (1u << q.normal_bits) - 1;
    m.normals.resize(vertex_count);
    for (size_t i = 0; i < vertex_count; ++i) {
      if (codes[i][0] > max_code || codes[i][1] > max_code) {
        return Corrupt(at + "vertex " + std::to_string(i) + ": normal code beyond " +
                       std::to_string(q.normal_bits) + " bits");
      }
      m.normals[i] = DecodeOctahedralNormal(codes[i][0], codes[i][1], q.normal_bits);
    }
    if (!GetGridColumns(&r, vertex_count, q.uv_exponent, &m.uvs)) {
      return Corrupt(at + "an atlas coordinate beyond 2^24 grid steps");
    }
  }
  GetColumns(&r, vertex_count, &m.joints);
  GetColumns(&r, vertex_count, &m.weights);
  if (quantised) {
    // Weights in 1/(2^b - 1) must sum to 2^b - 1; in 1/65535 they then sum
    // to 65535, which ValidateBodyModel checks.
    const uint32_t top = (1u << q.weight_bits) - 1, unit = WeightUnit(q.weight_bits);
    for (size_t i = 0; i < vertex_count; ++i) {
      uint32_t sum = 0;
      for (uint16_t& w : m.weights[i]) {
        sum += w;
        w = uint16_t(std::min<uint32_t>(w, top) * unit);
      }
      if (sum != top) {
        return Corrupt(at + "vertex " + std::to_string(i) + " skin weights sum to " +
                       std::to_string(sum) + ", not " + std::to_string(top));
      }
    }
  }
  const uint8_t* seg = r.Bytes(vertex_count);
  if (seg) m.segments.assign(seg, seg + vertex_count);
  GetTriangles(&r, triangle_count, &m.triangles);
  if (r.overrun() || r.remaining() != 0) return Internal(at + "mesh size bookkeeping");
  return ValidateBodyModel(*model, &limits);
}

}  // namespace

Status ValidateBodyModel(const BodyModel& model, const LevelLimits* limits) {
  const auto& bones = model.skeleton.bones;
  if (bones.empty()) return Corrupt("body model: skeleton has no bones");
  if (limits && bones.size() > limits->max_bones) {
    return LimitExceeded("body model: " + std::to_string(bones.size()) + " bones");
  }
  for (size_t i = 0; i < bones.size(); ++i) {
    const Bone& b = bones[i];
    const std::string at = "body model: bone " + std::to_string(i) + " ('" + b.name + "'): ";
    if (b.name.size() > kMaxBoneNameBytes) return Corrupt(at + "name longer than 255 bytes");
    if (b.parent < -1 || b.parent >= static_cast<int32_t>(i)) {
      return Corrupt(at + "parent " + std::to_string(b.parent) + " is not an earlier bone");
    }
    if (static_cast<uint8_t>(b.order) >= kRotationOrderCount) {
      return Corrupt(at + "rotation order " + std::to_string(int(b.order)) + " unknown");
    }
    if (b.dof_mask >= (1u << kDofKinds)) return Corrupt(at + "unknown DOF bits");
    double qn = 0;
    for (float v : b.rest_rotation) {
      if (!std::isfinite(v)) return Corrupt(at + "non-finite rest rotation");
      qn += double(v) * v;
    }
    if (std::fabs(qn - 1.0) > 1e-3) return Corrupt(at + "rest rotation is not a unit quaternion");
    for (float v : b.rest_translation) {
      if (!std::isfinite(v)) return Corrupt(at + "non-finite rest translation");
    }
    for (int k = 0; k < kDofKinds; ++k) {
      if ((b.dof_mask & (1u << k)) &&
          !(std::isfinite(b.dof_min[k]) && std::isfinite(b.dof_max[k]) &&
            b.dof_min[k] <= b.dof_max[k])) {
        return Corrupt(at + "DOF " + std::to_string(k) + " limits are not an interval");
      }
    }
  }
  const Mesh& m = model.mesh;
  const size_t n = m.positions.size();
  if (m.normals.size() != n || m.uvs.size() != n || m.joints.size() != n || m.weights.size() != n ||
      m.segments.size() != n) {
    return InvalidArgument("body model: per-vertex arrays differ in length");
  }
  if (limits && (n > limits->max_vertices || m.triangles.size() > limits->max_triangles)) {
    return LimitExceeded("body model: " + std::to_string(n) + " vertices, " +
                         std::to_string(m.triangles.size()) + " triangles beyond the level");
  }
  for (size_t i = 0; i < n; ++i) {
    uint32_t sum = 0;
    for (int k = 0; k < kMaxInfluences; ++k) {
      if (m.weights[i][k] != 0 && m.joints[i][k] >= bones.size()) {
        return Corrupt("body model: vertex " + std::to_string(i) + " is skinned to bone " +
                       std::to_string(m.joints[i][k]) + " of " + std::to_string(bones.size()));
      }
      sum += m.weights[i][k];
    }
    if (sum != 65535) {
      return Corrupt("body model: vertex " + std::to_string(i) + " skin weights sum to " +
                     std::to_string(sum) + ", not 65535");
    }
    for (float v : m.positions[i]) {
      if (!std::isfinite(v)) return Corrupt("body model: non-finite vertex position");
    }
  }
  for (size_t t = 0; t < m.triangles.size(); ++t) {
    for (uint32_t v : m.triangles[t]) {
      if (v >= n) {
        return Corrupt("body model: triangle " + std::to_string(t) + " uses vertex " +
                       std::to_string(v) + " of " + std::to_string(n));
      }
    }
  }
  return Status::Ok();
}

Status ReadModel(const BoxHeader& box, const uint8_t* payload, const LevelLimits& limits,
                 BodyModel* model) {
  const std::string at = BoxContext(box);
  if (box.version > 1) return Unsupported(at + "version " + std::to_string(box.version));
  ByteReader r(payload, box.payload_bytes());
  const uint8_t compression = r.U8();
  const uint32_t raw_size = r.U32();
  if (r.overrun()) return Corrupt(at + "too short");
  if (raw_size > MaxRawModelBytes(limits)) {
    return LimitExceeded(at + "model data of " + std::to_string(raw_size) +
                         " bytes exceeds what the level allows");
  }
  const uint8_t* data = payload + 5;
  const size_t size = static_cast<size_t>(box.payload_size() - 5);
  if (compression == kCompressionNone) {
    if (size != raw_size) return Corrupt(at + "stored model size does not match raw_size");
    return ParseRawModel(data, size, limits, box, model);
  }
  if (compression != kCompressionZstd) {
    return Unsupported(at + "compression method " + std::to_string(compression));
  }
  const StatusOr<uint64_t> content = ZstdContentSize(data, size);
  if (!content.ok() || *content != raw_size) {
    return Corrupt(at + "zstd frame does not declare raw_size " + std::to_string(raw_size));
  }
  std::vector<uint8_t> raw(raw_size);
  const Status unpacked = ZstdDecompress(data, size, &raw);
  if (!unpacked.ok()) return Corrupt(at + unpacked.message());
  return ParseRawModel(raw.data(), raw.size(), limits, box, model);
}

}  // namespace fvv
