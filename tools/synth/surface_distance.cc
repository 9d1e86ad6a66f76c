#include "tools/synth/surface_distance.h"

#include <Eigen/Core>
#include <array>
#include <cstdio>
#include <fstream>

#include "encoder/shape/surface_index.h"
#include "fvv/fvv_decoder.hpp"

namespace fvv {

StatusOr<std::vector<std::vector<double>>> DistanceToTrueSurface(const std::string& stream,
                                                                 const std::string& truth_dir,
                                                                 uint32_t frames) {
  DecoderPtr d = MakeDecoder();
  if (!d || fvv_decoder_open_file(d.get(), stream.c_str()) != FVV_OK) {
    return IoError(stream + ": " + (d ? fvv_decoder_error(d.get()) : "no decoder"));
  }
  fvv_model m;
  if (fvv_decoder_get_model(d.get(), &m) != FVV_OK) {
    return InvalidArgument(stream + ": " + fvv_decoder_error(d.get()));
  }
  std::vector<std::array<uint32_t, 3>> triangles(m.triangle_count);
  for (uint32_t t = 0; t < m.triangle_count; ++t) {
    triangles[t] = {m.triangles[3 * t], m.triangles[3 * t + 1], m.triangles[3 * t + 2]};
  }
  std::vector<std::vector<double>> out;
  for (uint32_t f = 0; f < frames; ++f) {
    FramePtr frame = DecodeFrame(d.get(), f, nullptr);
    if (!frame)
      return InvalidArgument(stream + ": frame " + std::to_string(f) + ": " +
                             fvv_decoder_error(d.get()));
    const float* bind = frame->surface ? frame->surface : m.positions;
    std::vector<Eigen::Vector3f> posed(m.vertex_count);
    for (uint32_t v = 0; v < m.vertex_count; ++v) {
      const Eigen::Vector4f x(bind[3 * v], bind[3 * v + 1], bind[3 * v + 2], 1.0f);
      Eigen::Vector4f p = Eigen::Vector4f::Zero();
      for (int k = 0; k < 4; ++k) {
        const float w = m.weights[4 * v + k];
        if (w == 0) continue;
        p += w * Eigen::Map<const Eigen::Matrix4f>(frame->bone_skin + 16 * m.joints[4 * v + k]) * x;
      }
      posed[v] = p.head<3>();
    }
    const SurfaceIndex surface(posed, triangles, 0.02);
    char name[48];
    std::snprintf(name, sizeof(name), "/surface_f%06u.bin", f);
    std::ifstream in(truth_dir + name, std::ios::binary | std::ios::ate);
    const std::streamoff bytes = in ? std::streamoff(in.tellg()) : 0;
    if (bytes < 12 || bytes % 12 != 0) {
      return IoError(truth_dir + name + ": no true surface (fvv synth writes one per frame)");
    }
    std::vector<float> truth(size_t(bytes) / 4);
    in.seekg(0);
    in.read(reinterpret_cast<char*>(truth.data()), std::streamsize(truth.size() * 4));
    if (!in.good()) return IoError(truth_dir + name + ": cannot read it");
    std::vector<double> dist(truth.size() / 3);
    for (size_t v = 0; v < dist.size(); ++v) {
      dist[v] = surface.Nearest(Eigen::Vector3d(truth[3 * v], truth[3 * v + 1], truth[3 * v + 2]));
    }
    out.push_back(std::move(dist));
  }
  return out;
}

}  // namespace fvv
