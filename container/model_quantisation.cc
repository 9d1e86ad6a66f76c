#include "container/model_quantisation.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>

#include "container/body_model.h"

namespace fvv {
namespace {

// The octahedral code's integer direction (SPEC.md 3.3.1): odd coordinates,
// so none is zero and the vector never vanishes.
std::array<int64_t, 3> OctahedralDirection(uint32_t u, uint32_t v, int bits) {
  const int64_t m = (int64_t{1} << bits) - 1;
  int64_t x = 2 * int64_t{u} - m, y = 2 * int64_t{v} - m;
  const int64_t z = m - std::llabs(x) - std::llabs(y);
  if (z < 0) {
    const int64_t fx = (m - std::llabs(y)) * (x >= 0 ? 1 : -1);
    const int64_t fy = (m - std::llabs(x)) * (y >= 0 ? 1 : -1);
    x = fx;
    y = fy;
  }
  return {x, y, z};
}

int64_t Nearest(double x, int64_t lo, int64_t hi) {
  return std::min(hi, std::max(lo, int64_t(std::llround(x))));
}

bool SnapValue(float* x, int exponent) {
  const double q = GridSteps(*x, exponent);
  if (!(std::fabs(q) <= double(kMaxQuantisedMagnitude))) return false;  // NaN too
  // Through an integer, as a decoder gets it: -0.0 becomes +0.0.
  *x = GridFloat(int64_t(q), exponent);
  return true;
}

}  // namespace

ModelQuantisation DefaultModelQuantisation(uint32_t atlas_side) {
  ModelQuantisation q;
  q.quantised = true;
  q.position_exponent = 13;
  int log2_side = 0;
  while ((uint64_t{1} << log2_side) < atlas_side) ++log2_side;
  q.uv_exponent = uint8_t(std::min(kMaxQuantisationExponent, log2_side + 6));
  q.normal_bits = 10;
  q.weight_bits = 8;
  return q;
}

Status ValidateModelQuantisation(const ModelQuantisation& q) {
  if (q.position_exponent > kMaxQuantisationExponent) {
    return Corrupt("position exponent " + std::to_string(q.position_exponent) + " above 30");
  }
  if (q.uv_exponent > kMaxQuantisationExponent) {
    return Corrupt("atlas coordinate exponent " + std::to_string(q.uv_exponent) + " above 30");
  }
  if (q.normal_bits < 2 || q.normal_bits > 16) {
    return Corrupt("normal bits " + std::to_string(q.normal_bits) + " outside 2..16");
  }
  if (q.weight_bits == 0 || q.weight_bits > 16 || 16 % q.weight_bits != 0) {
    return Corrupt("weight bits " + std::to_string(q.weight_bits) + " not 1, 2, 4, 8 or 16");
  }
  return Status::Ok();
}

std::array<float, 3> DecodeOctahedralNormal(uint32_t u, uint32_t v, int bits) {
  const std::array<int64_t, 3> d = OctahedralDirection(u, v, bits);
  const double length = std::sqrt(double(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]));
  return {float(double(d[0]) / length), float(double(d[1]) / length), float(double(d[2]) / length)};
}

std::array<uint32_t, 2> EncodeOctahedralNormal(const std::array<float, 3>& n, int bits) {
  const int64_t m = (int64_t{1} << bits) - 1;
  const double l1 = std::fabs(double(n[0])) + std::fabs(double(n[1])) + std::fabs(double(n[2]));
  if (!(l1 > 0) || !std::isfinite(l1)) {  // no direction: +z
    return {uint32_t((m + 1) / 2), uint32_t((m + 1) / 2)};
  }
  double px = n[0] / l1, py = n[1] / l1;
  if (n[2] < 0) {
    const double fx = (1 - std::fabs(py)) * (px >= 0 ? 1 : -1);
    const double fy = (1 - std::fabs(px)) * (py >= 0 ? 1 : -1);
    px = fx;
    py = fy;
  }
  const int64_t u0 = Nearest((px + 1) * 0.5 * double(m), 0, m);
  const int64_t v0 = Nearest((py + 1) * 0.5 * double(m), 0, m);
  // Rounding in the plane is not nearest on the sphere: the best of the
  // neighbouring codes by angle.
  std::array<uint32_t, 2> best = {uint32_t(u0), uint32_t(v0)};
  double best_cos = -2;
  for (int64_t u = std::max<int64_t>(0, u0 - 1); u <= std::min(m, u0 + 1); ++u) {
    for (int64_t v = std::max<int64_t>(0, v0 - 1); v <= std::min(m, v0 + 1); ++v) {
      const std::array<int64_t, 3> d = OctahedralDirection(uint32_t(u), uint32_t(v), bits);
      const double dot = double(d[0]) * n[0] + double(d[1]) * n[1] + double(d[2]) * n[2];
      const double cos = dot / std::sqrt(double(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]));
      if (cos > best_cos) {
        best_cos = cos;
        best = {uint32_t(u), uint32_t(v)};
      }
    }
  }
  return best;
}

std::array<uint32_t, 4> QuantiseWeights(const std::array<uint16_t, 4>& w, int bits) {
  const uint64_t top = (uint64_t{1} << bits) - 1;
  std::array<uint32_t, 4> q{};
  std::array<uint64_t, 4> rest{};
  uint64_t sum = 0;
  for (int k = 0; k < 4; ++k) {
    q[k] = uint32_t(w[k] * top / 65535);
    rest[k] = w[k] * top % 65535;
    sum += q[k];
  }
  // The remainders sum to a whole number of units when the weights sum to
  // 65535; each unit goes to the largest remainder left (the first on ties).
  while (sum < top) {
    int k = 0;
    for (int j = 1; j < 4; ++j) {
      if (rest[j] > rest[k]) k = j;
    }
    if (rest[k] == 0) break;  // the input did not sum to 65535
    ++q[k];
    rest[k] = 0;
    ++sum;
  }
  return q;
}

Status QuantiseModel(const ModelQuantisation& q, BodyModel* model) {
  if (!q.quantised) return InvalidArgument("QuantiseModel: a grid that does not quantise");
  const Status valid = ValidateModelQuantisation(q);
  if (!valid.ok()) return InvalidArgument("model quantisation: " + valid.message());
  Mesh& m = model->mesh;
  for (auto& p : m.positions) {
    for (float& x : p) {
      if (!SnapValue(&x, q.position_exponent)) {
        return InvalidArgument("body model: a vertex position lies beyond the quantisation grid");
      }
    }
  }
  for (auto& uv : m.uvs) {
    for (float& x : uv) {
      if (!SnapValue(&x, q.uv_exponent)) {
        return InvalidArgument("body model: an atlas coordinate lies beyond the quantisation grid");
      }
    }
  }
  for (auto& n : m.normals) {
    const std::array<uint32_t, 2> code = EncodeOctahedralNormal(n, q.normal_bits);
    n = DecodeOctahedralNormal(code[0], code[1], q.normal_bits);
  }
  const uint32_t unit = WeightUnit(q.weight_bits);
  for (auto& w : m.weights) {
    const std::array<uint32_t, 4> qw = QuantiseWeights(w, q.weight_bits);
    for (int k = 0; k < 4; ++k) w[k] = uint16_t(qw[k] * unit);
  }
  model->quantisation = q;
  return Status::Ok();
}

}  // namespace fvv
