// Mask-coder benchmark: bits per mask texel of the fvv context coder against
// zstd -19 (bit-packed and one byte per texel) on the same GOP of masks, with
// encode/decode times, measured side by side.
//
//   build/bench/mask_bench [--size N] [--dir DIR --frames F --cameras C]
// Built-in inputs: (1) the sample volume's moving elliptical masks; (2) atlas
// visibility masks of the sample body model (texels of triangles facing each
// camera of a ring while the actor turns). --dir reads DIR/mask_tTTT_cCC.png
// (the layout `fvv block sample` writes) instead.
#include <zstd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "codec/mask_coder.h"
#include "encoder/sample/sample_stream.h"
#include "encoder/sample/sample_volume.h"
#include "tools/imageio/image_io.h"

namespace fvv {
namespace {

using Clock = std::chrono::steady_clock;
double Ms(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

size_t Zstd(const std::vector<uint8_t>& v) {
  std::vector<uint8_t> out(ZSTD_compressBound(v.size()));
  const size_t n = ZSTD_compress(out.data(), out.size(), v.data(), v.size(), 19);
  return ZSTD_isError(n) ? 0 : n;
}

std::vector<uint8_t> PackBits(const std::vector<uint8_t>& m) {
  std::vector<uint8_t> p((m.size() + 7) / 8, 0);
  for (size_t i = 0; i < m.size(); ++i) p[i / 8] |= static_cast<uint8_t>((m[i] != 0) << (i % 8));
  return p;
}

std::vector<uint8_t> EllipseMasks(const Shape4D& s) {
  std::vector<uint8_t> m(s.count());
  for (uint32_t t = 0; t < s.frames(); ++t)
    for (uint32_t c = 0; c < s.cameras(); ++c) {
      const Image img = SampleMask(t, c, s.width(), s.height());
      for (size_t i = 0; i < img.pixels.size(); ++i)
        m[s.Index(t, c, 0, 0) + i] = img.pixels[i] != 0;
    }
  return m;
}

// Texels of the sample model's triangles that face camera c at frame t.
std::vector<uint8_t> AtlasVisibilityMasks(const Shape4D& s) {
  const BodyModel model = MakeSampleBodyModel();
  const std::vector<Camera> cams = MakeRingCameras(s.cameras(), 640, 480);
  const Mesh& mesh = model.mesh;
  std::vector<uint8_t> m(s.count(), 0);
  for (uint32_t t = 0; t < s.frames(); ++t) {
    const double turn = 0.15 * t;
    for (uint32_t c = 0; c < s.cameras(); ++c) {
      const auto centre = cams[c].Centre();
      uint8_t* plane = m.data() + s.Index(t, c, 0, 0);
      for (const auto& tri : mesh.triangles) {
        const auto& n = mesh.normals[tri[0]];
        const auto& p = mesh.positions[tri[0]];
        const double nx = n[0] * std::cos(turn) + n[2] * std::sin(turn);
        const double nz = -n[0] * std::sin(turn) + n[2] * std::cos(turn);
        const double px = p[0] * std::cos(turn) + p[2] * std::sin(turn);
        const double pz = -p[0] * std::sin(turn) + p[2] * std::cos(turn);
        if (nx * (centre[0] - px) + n[1] * (centre[1] - p[1]) + nz * (centre[2] - pz) <= 0)
          continue;
        double u[3], v[3];
        for (int k = 0; k < 3; ++k) {
          u[k] = mesh.uvs[tri[k]][0] * s.width();
          v[k] = mesh.uvs[tri[k]][1] * s.height();
        }
        const double area = (u[1] - u[0]) * (v[2] - v[0]) - (u[2] - u[0]) * (v[1] - v[0]);
        if (area == 0) continue;
        const int x0 = std::max(0, int(std::floor(std::min({u[0], u[1], u[2]}))));
        const int x1 = std::min(int(s.width()) - 1, int(std::ceil(std::max({u[0], u[1], u[2]}))));
        const int y0 = std::max(0, int(std::floor(std::min({v[0], v[1], v[2]}))));
        const int y1 = std::min(int(s.height()) - 1, int(std::ceil(std::max({v[0], v[1], v[2]}))));
        for (int y = y0; y <= y1; ++y)
          for (int x = x0; x <= x1; ++x) {
            const double px2 = x + 0.5, py2 = y + 0.5;
            const double w0 = ((u[1] - px2) * (v[2] - py2) - (u[2] - px2) * (v[1] - py2)) / area;
            const double w1 = ((u[2] - px2) * (v[0] - py2) - (u[0] - px2) * (v[2] - py2)) / area;
            if (w0 >= 0 && w1 >= 0 && w0 + w1 <= 1) plane[size_t(y) * s.width() + x] = 1;
          }
      }
    }
  }
  return m;
}

Status LoadDir(const std::string& dir, Shape4D* s, std::vector<uint8_t>* m) {
  for (uint32_t t = 0; t < s->frames(); ++t)
    for (uint32_t c = 0; c < s->cameras(); ++c) {
      char name[64];
      std::snprintf(name, sizeof(name), "/mask_t%03u_c%02u.png", t, c);
      FVV_ASSIGN_OR_RETURN(Image img, ReadImage(dir + name));
      if (t == 0 && c == 0) {
        s->n[2] = img.height;
        s->n[3] = img.width;
        m->assign(s->count(), 0);
      }
      if (img.width != s->width() || img.height != s->height()) {
        return InvalidArgument(dir + name + ": size differs from the first mask");
      }
      for (size_t i = 0; i < size_t{img.width} * img.height; ++i) {
        (*m)[s->Index(t, c, 0, 0) + i] = img.pixels[i * img.channels] != 0;
      }
    }
  return Status::Ok();
}

void Report(const char* name, const Shape4D& s, const std::vector<uint8_t>& m) {
  auto t0 = Clock::now();
  const std::vector<uint8_t> coded = EncodeMasks(m.data(), s);
  const double enc_ms = Ms(t0);
  std::vector<uint8_t> back(s.count());
  t0 = Clock::now();
  const Status st = DecodeMasks(coded.data(), coded.size(), s, back.data());
  const double dec_ms = Ms(t0);
  if (!st.ok() || back != m) {
    std::fprintf(stderr, "mask_bench: %s: round trip failed\n", name);
    std::exit(1);
  }
  t0 = Clock::now();
  const size_t zpacked = Zstd(PackBits(m));
  const double z_ms = Ms(t0);
  const size_t zbytes = Zstd(m);
  size_t used = 0;
  for (uint8_t v : m) used += v;
  const double texels = double(s.count());
  std::printf("%-22s %5.1f%% | %8.5f %8.5f %8.5f | %6.2fx %6.2fx | %7.1f %7.1f %7.1f\n", name,
              100.0 * used / texels, coded.size() * 8 / texels, zpacked * 8 / texels,
              zbytes * 8 / texels, double(zpacked) / coded.size(), double(zbytes) / coded.size(),
              enc_ms, dec_ms, z_ms);
}

}  // namespace
}  // namespace fvv

int main(int argc, char** argv) {
  using namespace fvv;
  uint32_t size = 512, frames = 8, cameras = 8;
  std::string dir;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--size" && i + 1 < argc)
      size = std::atoi(argv[++i]);
    else if (a == "--dir" && i + 1 < argc)
      dir = argv[++i];
    else if (a == "--frames" && i + 1 < argc)
      frames = std::atoi(argv[++i]);
    else if (a == "--cameras" && i + 1 < argc)
      cameras = std::atoi(argv[++i]);
    else {
      std::printf("usage: %s [--size N] [--dir DIR --frames F --cameras C]\n", argv[0]);
      return a == "-h" || a == "--help" ? 0 : 2;
    }
  }
  Shape4D s;
  s.n = {frames, cameras, size, size};
  std::printf(
      "masks: one GOP of %u frames x %u cameras; bits per texel, zstd -19 over the whole GOP\n",
      frames, cameras);
  std::printf("%-22s %6s | %8s %8s %8s | %7s %7s | %7s %7s %7s\n", "input", "used", "fvv",
              "zstd bit", "zstd B", "vs bit", "vs B", "enc ms", "dec ms", "zstd ms");
  if (!dir.empty()) {
    std::vector<uint8_t> m;
    Status st = LoadDir(dir, &s, &m);
    if (!st.ok()) {
      std::fprintf(stderr, "mask_bench: %s\n", st.ToString().c_str());
      return 1;
    }
    Report(dir.c_str(), s, m);
    return 0;
  }
  Report("sample ellipses", s, EllipseMasks(s));
  Report("model atlas visibility", s, AtlasVisibilityMasks(s));
  return 0;
}
