#include "container/surface_displacement.h"

#include <cmath>
#include <string>

#include "container/zstd_frame.h"

namespace fvv {

Status DecodeSurfaceDisplacements(const uint8_t* data, size_t size, uint32_t frames,
                                  uint32_t vertices, std::vector<int32_t>* values) {
  const uint64_t count = uint64_t{frames} * vertices;
  FVV_ASSIGN_OR_RETURN(const uint64_t content, ZstdContentSize(data, size));
  if (content < count || content > count * kMaxSurfaceResidualBytes) {
    return Corrupt("surface: the zstd frame declares " + std::to_string(content) + " bytes for " +
                   std::to_string(count) + " values (" + std::to_string(count) + ".." +
                   std::to_string(count * kMaxSurfaceResidualBytes) + " allowed)");
  }
  std::vector<uint8_t> bytes(static_cast<size_t>(content));
  FVV_RETURN_IF_ERROR(ZstdDecompress(data, size, &bytes));
  values->assign(static_cast<size_t>(count), 0);
  size_t pos = 0;
  for (uint32_t t = 0; t < frames; ++t) {
    for (uint32_t v = 0; v < vertices; ++v) {
      uint64_t r = 0;
      for (int shift = 0;; shift += 7) {
        if (pos == bytes.size() || shift > 28) {
          return Corrupt("surface: residual of frame " + std::to_string(t) + ", vertex " +
                         std::to_string(v) +
                         (pos == bytes.size() ? " runs past the data" : " is longer than 5 bytes"));
        }
        const uint8_t b = bytes[pos++];
        r |= uint64_t{b & 0x7Fu} << shift;
        if (!(b & 0x80)) break;
      }
      if (r > 0xFFFFFFFFu) {
        return Corrupt("surface: residual of frame " + std::to_string(t) + ", vertex " +
                       std::to_string(v) + " exceeds 32 bits");
      }
      const int64_t residual = int64_t(r >> 1) ^ -int64_t(r & 1);
      const int64_t value = PredictSurfaceValue(values->data(), vertices, t, v) + residual;
      if (value > kMaxSurfaceValue || value < -kMaxSurfaceValue) {
        return Corrupt("surface: value " + std::to_string(value) + " of frame " +
                       std::to_string(t) + ", vertex " + std::to_string(v) + " exceeds " +
                       std::to_string(kMaxSurfaceValue));
      }
      (*values)[size_t(t) * vertices + v] = static_cast<int32_t>(value);
    }
  }
  if (pos != bytes.size()) {
    return Corrupt("surface: " + std::to_string(bytes.size() - pos) +
                   " bytes follow the last residual");
  }
  return Status::Ok();
}

void SurfacePositions(const Mesh& mesh, const int32_t* values, uint8_t step_exponent,
                      std::vector<float>* out) {
  const size_t n = mesh.positions.size();
  out->resize(n * 3);
  const double step = std::ldexp(1.0, -int(step_exponent));
  for (size_t v = 0; v < n; ++v) {
    const double d = double(values[v]) * step;  // exact: a power of two
    for (int k = 0; k < 3; ++k) {
      // The product is exact in binary64 (21 + 24 significant bits).
      const double sum = double(mesh.positions[v][k]) + d * double(mesh.normals[v][k]);
      (*out)[v * 3 + k] = static_cast<float>(sum);
    }
  }
}

}  // namespace fvv
