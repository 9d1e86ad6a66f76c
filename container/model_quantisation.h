// The grid a 'modl' version 1 box stores the mesh on (SPEC.md 3.3.1):
// positions and atlas coordinates in power-of-two steps, normals as
// octahedral codes, skin weights in fewer bits. The decoded values are exact
// functions of the stored integers, so every decoder gets the same floats, and
// an encoder that snaps its model first (QuantiseModel) resamples its
// textures with the model the players will draw.
#ifndef FVV_CONTAINER_MODEL_QUANTISATION_H_
#define FVV_CONTAINER_MODEL_QUANTISATION_H_

#include <array>
#include <cmath>
#include <cstdint>

#include "codec/base/status.h"

namespace fvv {

struct BodyModel;

struct ModelQuantisation {
  bool quantised = false;         // false: 'modl' version 0, 32-bit floats
  uint8_t position_exponent = 0;  // positions in steps of 2^-e metres
  uint8_t uv_exponent = 0;        // atlas coordinates in steps of 2^-e
  uint8_t normal_bits = 0;        // bits per octahedral coordinate, 2..16
  uint8_t weight_bits = 0;        // skin weights in 1/(2^b - 1); b divides 16
  bool operator==(const ModelQuantisation& o) const {
    return quantised == o.quantised && position_exponent == o.position_exponent &&
           uv_exponent == o.uv_exponent && normal_bits == o.normal_bits &&
           weight_bits == o.weight_bits;
  }
  bool operator!=(const ModelQuantisation& o) const { return !(*this == o); }
};

// Largest magnitude of a stored position or atlas coordinate, in steps: below
// 2^24 the decoded float is the exact product.
constexpr int64_t kMaxQuantisedMagnitude = (int64_t{1} << 24) - 1;
constexpr int kMaxQuantisationExponent = 30;

// The reference encoder's grid: 2^-13 m (0.12 mm), 1/64 of a texel of an
// atlas of `atlas_side`, 10-bit octahedral normals, 8-bit weights.
ModelQuantisation DefaultModelQuantisation(uint32_t atlas_side);

// The nearest grid value of x in steps of 2^-exponent (half away from zero),
// and the float a decoder makes of a grid value.
inline double GridSteps(float x, int exponent) {
  return std::round(std::ldexp(double(x), exponent));
}
inline float GridFloat(int64_t value, int exponent) { return std::ldexp(float(value), -exponent); }
// A skin weight in 1/(2^bits - 1) is this many units of 1/65535.
inline uint32_t WeightUnit(int bits) { return 65535u / ((1u << bits) - 1); }

// Checks the grid's fields against their ranges (Corrupt names the field).
Status ValidateModelQuantisation(const ModelQuantisation& q);

// The unit normal of octahedral code (u, v) with `bits` per coordinate, as
// SPEC.md 3.3.1 defines it bit for bit.
std::array<float, 3> DecodeOctahedralNormal(uint32_t u, uint32_t v, int bits);
// The code whose decoded normal is closest in angle to n (n need not be unit
// length). A normal that is itself a decoded code gets that code back.
std::array<uint32_t, 2> EncodeOctahedralNormal(const std::array<float, 3>& n, int bits);

// Skin weights in 1/65535 (summing to 65535) to weights in 1/(2^bits - 1)
// summing to 2^bits - 1, by largest remainder.
std::array<uint32_t, 4> QuantiseWeights(const std::array<uint16_t, 4>& w, int bits);

// Moves every position, atlas coordinate, normal and weight of `model` to
// the nearest value of grid `q` (what a decoder of its 'modl' version 1 box
// gets) and records q in model->quantisation. InvalidArgument when a value
// lies beyond the grid's range.
Status QuantiseModel(const ModelQuantisation& q, BodyModel* model);

}  // namespace fvv

#endif  // FVV_CONTAINER_MODEL_QUANTISATION_H_
