// Mask-coder benchmark: bits per mask texel of the fvv mask coder (mode 1:
// context coding; mode 2: mixed context models) against zstd -19 (bit-packed
// and one byte per texel) on the same GOPs of masks, with encode/decode times,
// measured side by side.
//
//   build/bench/mask_bench [--size N] [--dir DIR --frames F --cameras C [--gops G]]
// Built-in inputs: (1) the sample volume's moving elliptical masks; (2) atlas
// visibility masks of the sample body model (texels of triangles facing each
// camera of a ring while the actor turns). --dir reads masks from a directory
// instead: DIR/camCC/mask_FFFFFF.png (what `fvv encode --save-textures` writes)
// or DIR/mask_tTTT_cCC.png (what `fvv block sample` writes); G consecutive GOPs
// of F frames, each camera of the C its own GOP when C is 1 (the encoder's
// default shape), are summed.
#include <zstd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "codec/mask.h"
#include "conformance/sample/sample_stream.h"
#include "conformance/sample/sample_volume.h"
#include "encoder/io/image_io.h"

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

// Frames first_frame.. of cameras first_camera.. of a mask directory.
Status LoadDir(const std::string& dir, uint32_t first_frame, uint32_t first_camera, Shape4D* s,
               std::vector<uint8_t>* m) {
  const bool encoder_layout = ReadImage(dir + "/cam00/mask_000000.png").ok();
  for (uint32_t t = 0; t < s->frames(); ++t)
    for (uint32_t c = 0; c < s->cameras(); ++c) {
      char name[64];
      if (encoder_layout) {
        std::snprintf(name, sizeof(name), "/cam%02u/mask_%06u.png", first_camera + c,
                      first_frame + t);
      } else {
        std::snprintf(name, sizeof(name), "/mask_t%03u_c%02u.png", first_frame + t,
                      first_camera + c);
      }
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

// Sizes and times summed over GOPs.
struct Tally {
  double texels = 0, used = 0;
  size_t coded[2] = {0, 0}, zpacked = 0, zbytes = 0;
  double enc_ms[2] = {0, 0}, dec_ms[2] = {0, 0}, z_ms = 0;

  void Add(const Shape4D& s, const std::vector<uint8_t>& m) {
    for (int k = 0; k < 2; ++k) {
      const MaskCoding mode = k == 0 ? MaskCoding::kContext : MaskCoding::kMixing;
      auto t0 = Clock::now();
      const std::vector<uint8_t> coded_masks = EncodeMasks(m.data(), s, mode);
      enc_ms[k] += Ms(t0);
      std::vector<uint8_t> back(s.count());
      t0 = Clock::now();
      const Status st = DecodeMasks(coded_masks.data(), coded_masks.size(), s, mode, back.data());
      dec_ms[k] += Ms(t0);
      if (!st.ok() || back != m) {
        std::fprintf(stderr, "mask_bench: mode %d: round trip failed\n", k + 1);
        std::exit(1);
      }
      coded[k] += coded_masks.size();
    }
    auto t0 = Clock::now();
    zpacked += Zstd(PackBits(m));
    z_ms += Ms(t0);
    zbytes += Zstd(m);
    for (uint8_t v : m) used += v;
    texels += double(s.count());
  }
  void Print(const char* name) const {
    for (int k = 0; k < 2; ++k) {
      std::printf("%-22s %d %5.1f%% | %8.5f %8.5f %8.5f | %6.2fx %6.2fx | %7.1f %7.1f %7.1f\n",
                  name, k + 1, 100.0 * used / texels, coded[k] * 8 / texels, zpacked * 8 / texels,
                  zbytes * 8 / texels, double(zpacked) / coded[k], double(zbytes) / coded[k],
                  enc_ms[k], dec_ms[k], z_ms);
    }
  }
};

void Report(const char* name, const Shape4D& s, const std::vector<uint8_t>& m) {
  Tally t;
  t.Add(s, m);
  t.Print(name);
}

}  // namespace
}  // namespace fvv

int main(int argc, char** argv) {
  using namespace fvv;
  uint32_t size = 512, frames = 8, cameras = 8, gops = 1;
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
    else if (a == "--gops" && i + 1 < argc)
      gops = std::atoi(argv[++i]);
    else {
      std::printf("usage: %s [--size N] [--dir DIR --frames F --cameras C [--gops G]]\n", argv[0]);
      return a == "-h" || a == "--help" ? 0 : 2;
    }
  }
  Shape4D s;
  s.n = {frames, cameras, size, size};
  std::printf(
      "masks: one GOP of %u frames x %u cameras; bits per texel, zstd -19 over the whole GOP\n",
      frames, cameras);
  std::printf("%-22s %s %6s | %8s %8s %8s | %7s %7s | %7s %7s %7s\n", "input", "m", "used", "fvv",
              "zstd bit", "zstd B", "vs bit", "vs B", "enc ms", "dec ms", "zstd ms");
  if (!dir.empty()) {
    // With --cameras 1, every camera of the directory is a GOP of its own.
    Tally tally;
    for (uint32_t g = 0; g < gops; ++g) {
      for (uint32_t c0 = 0;; c0 += cameras) {
        std::vector<uint8_t> m;
        Shape4D gop = s;
        const Status st = LoadDir(dir, g * frames, c0, &gop, &m);
        if (!st.ok()) {
          if (c0 > 0) break;  // past the last camera
          std::fprintf(stderr, "mask_bench: %s\n", st.ToString().c_str());
          return 1;
        }
        tally.Add(gop, m);
        if (cameras != 1) break;
      }
    }
    std::printf("(%u GOPs of %u frames x %s)\n", gops, frames,
                cameras == 1 ? "1 camera, every camera" : std::to_string(cameras).c_str());
    tally.Print(dir.c_str());
    return 0;
  }
  Report("sample ellipses", s, EllipseMasks(s));
  Report("model atlas visibility", s, AtlasVisibilityMasks(s));
  return 0;
}
