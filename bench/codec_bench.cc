// Texture codec benchmark (a program, not a test).
//   codec_bench kodak DATA_DIR [--images N]   2D: every kernel x coder against OpenJPEG
//   codec_bench gop4d DATA_DIR                4D: an 8x8x512x512 GOP built from Kodak views
// OpenJPEG runs side by side in the same process run (opj_compress -I, 9/7, at our byte count).
#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "codec/base/sample_pool.h"
#include "codec/base/thread_pool.h"
#include "codec/block_codec.h"
#include "codec/colour.h"
#include "encoder/io/image_io.h"

namespace fvv {
namespace {

using Clock = std::chrono::steady_clock;
double Secs(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

double PsnrRgb(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  double s = 0;
  for (size_t i = 0; i < a.size(); ++i) s += (double(a[i]) - b[i]) * (double(a[i]) - b[i]);
  return PsnrFromMse(s / a.size());
}
double PsnrY(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  double s = 0;
  const size_t n = a.size() / 3;
  for (size_t i = 0; i < n; ++i) {
    const double ya = RgbToYuv(ColourSpace::kYCbCr601, a[3 * i], a[3 * i + 1], a[3 * i + 2]).y;
    const double yb = RgbToYuv(ColourSpace::kYCbCr601, b[3 * i], b[3 * i + 1], b[3 * i + 2]).y;
    s += (ya - yb) * (ya - yb);
  }
  return PsnrFromMse(s / n);
}

bool WritePpm(const std::string& path, const Image& img) {
  std::ofstream f(path, std::ios::binary);
  f << "P6\n" << img.width << " " << img.height << "\n255\n";
  f.write(reinterpret_cast<const char*>(img.pixels.data()), img.pixels.size());
  return bool(f);
}
bool ReadPpm(const std::string& path, std::vector<uint8_t>* rgb) {
  std::ifstream f(path, std::ios::binary);
  std::string magic;
  int w, h, maxv;
  f >> magic;
  auto skip_comments = [&f] {  // opj_decompress writes "# OpenJPEG-..." into the header
    while (f >> std::ws && f.peek() == '#') f.ignore(1 << 20, '\n');
  };
  skip_comments();
  f >> w;
  skip_comments();
  f >> h;
  skip_comments();
  f >> maxv;
  f.get();
  if (!f || w <= 0 || h <= 0 || maxv != 255) return false;
  rgb->resize(size_t(w) * h * 3);
  f.read(reinterpret_cast<char*>(rgb->data()), rgb->size());
  return bool(f) && magic == "P6";
}

struct Row {
  double psnr_rgb = 0, psnr_y = 0, enc_ms = 0, dec_ms = 0, bytes = 0;
  int n = 0;
  void Add(double pr, double py, double e, double d, double b) {
    psnr_rgb += pr, psnr_y += py, enc_ms += e, dec_ms += d, bytes += b, ++n;
  }
};

int Kodak(const std::string& dir, int images, bool only_97_arith) {
  const double rates[] = {0.125, 0.25, 0.5, 1.0};
  const char* kernels[] = {"haar", "53", "97"};
  // Own-band weights (format version 6) for all, and with the 9/7 samples with
  // 3 fractional bits (format version 7) but for "a3whole", arith3 with whole
  // samples (version 6), and "a3axis", that with the per-axis weights of
  // format version 5: the comparisons.
  const char* coders[] = {"binary", "arith", "arith2", "arith3", "a3whole", "a3axis", "arith4"};
  constexpr int kCoders = 7, kDefaultCoder = 3;  // arith3: what fvv encode writes
  constexpr int kQuadtreeCoder = 6;              // arith4: quadtrees per band
  Row rows[3][kCoders][4], opj[4];
  ThreadPool pool(1);  // single-threaded on both sides: OpenJPEG's CLI codes on one thread
  const std::string tmp = "/tmp/fvv_bench_" + std::to_string(getpid());
  double samples_total = 0;
  for (int i = 1; i <= images; ++i) {
    char name[64];
    std::snprintf(name, sizeof name, "/kodak/kodim%02d.png", i);
    auto img = ReadImage(dir + name);
    if (!img.ok()) {
      std::fprintf(stderr, "skip: %s\n", img.status().ToString().c_str());
      return 0;
    }
    const Shape4D shape{{1, 1, img->height, img->width}};
    samples_total += shape.count();
    const Block whole =
        BlockFromRgb(img->pixels.data(), shape, ColourSpace::kYCbCr601, ChromaFormat::k444);
    const Block fractional = BlockFromRgb(img->pixels.data(), shape, ColourSpace::kYCbCr601,
                                          ChromaFormat::k444, kDefaultSampleFrac);
    std::fprintf(stderr, "kodim%02d ", i);
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < kCoders; ++c)
        for (int r = 0; r < 4; ++r) {
          if (only_97_arith && !(k == 2 && c > 0)) continue;
          EncodeSettings s;
          s.kernel = static_cast<WaveletKernel>(k);
          s.coder = c == kQuadtreeCoder ? EntropyCoder::kQuadtree
                                        : static_cast<EntropyCoder>(c < 4 ? c : 3);
          if (c == 5) s.weights = BandWeights::kAxisBands;
          const Block& block = k == 2 && (c < 4 || c == kQuadtreeCoder) ? fractional : whole;
          s.rate_value = rates[r];
          s.runner = pool.runner();
          auto t0 = Clock::now();
          auto enc = EncodeBlock(block, nullptr, s);
          const double e = Secs(t0);
          t0 = Clock::now();
          auto dec = DecodeBlock(*enc, {}, pool.runner());
          const double d = Secs(t0);
          std::vector<uint8_t> out(img->pixels.size());
          BlockToRgb(*dec, out.data());
          rows[k][c][r].Add(PsnrRgb(img->pixels, out), PsnrY(img->pixels, out), e * 1e3, d * 1e3,
                            double(enc->total_bytes()));
          if (k == 2 && c == kDefaultCoder) {
            // OpenJPEG 9/7 at the same total bytes (its file includes ~200 header bytes).
            const double ratio = double(img->pixels.size()) / double(enc->total_bytes());
            WritePpm(tmp + ".ppm", *img);
            const std::string cmd_c = "opj_compress -i " + tmp + ".ppm -o " + tmp + ".j2k -I -r " +
                                      std::to_string(ratio) + " >/dev/null 2>&1";
            t0 = Clock::now();
            if (std::system(cmd_c.c_str()) != 0) {
              std::fprintf(stderr, "opj_compress failed\n");
              return 1;
            }
            const double oe = Secs(t0);
            const std::string cmd_d =
                "opj_decompress -i " + tmp + ".j2k -o " + tmp + "_d.ppm >/dev/null 2>&1";
            t0 = Clock::now();
            if (std::system(cmd_d.c_str()) != 0) {
              std::fprintf(stderr, "opj_decompress failed\n");
              return 1;
            }
            const double od = Secs(t0);
            std::vector<uint8_t> o;
            if (!ReadPpm(tmp + "_d.ppm", &o) || o.size() != img->pixels.size()) {
              std::fprintf(stderr, "cannot read OpenJPEG's output %s_d.ppm\n", tmp.c_str());
              return 1;
            }
            std::ifstream jf(tmp + ".j2k", std::ios::binary | std::ios::ate);
            opj[r].Add(PsnrRgb(img->pixels, o), PsnrY(img->pixels, o), oe * 1e3, od * 1e3,
                       double(jf.tellg()));
          }
        }
  }
  std::fprintf(stderr, "\n");
  std::remove((tmp + ".ppm").c_str());
  std::remove((tmp + ".j2k").c_str());
  std::remove((tmp + "_d.ppm").c_str());
  const double per_image = samples_total / images;
  std::printf(
      "Kodak, %d images, mean over images; 1 thread; OpenJPEG 2.5 (opj_compress -I -r, process "
      "time incl. start-up)\n",
      images);
  std::printf("%-14s %6s %9s %9s %9s %10s %10s\n", "codec", "bpp", "bytes", "RGB dB", "Y dB",
              "enc MS/s", "dec MS/s");
  for (int r = 0; r < 4; ++r) {
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < kCoders; ++c) {
        const Row& x = rows[k][c][r];
        if (x.n == 0) continue;
        std::printf("fvv %-4s %-6s %6.3f %9.0f %9.2f %9.2f %10.1f %10.1f\n", kernels[k], coders[c],
                    rates[r], x.bytes / x.n, x.psnr_rgb / x.n, x.psnr_y / x.n,
                    per_image / (x.enc_ms / x.n) / 1e3, per_image / (x.dec_ms / x.n) / 1e3);
      }
    const Row& o = opj[r];
    std::printf("%-14s %6.3f %9.0f %9.2f %9.2f %10.1f %10.1f\n", "openjpeg 9/7", rates[r],
                o.bytes / o.n, o.psnr_rgb / o.n, o.psnr_y / o.n, per_image / (o.enc_ms / o.n) / 1e3,
                per_image / (o.dec_ms / o.n) / 1e3);
    const Row& f = rows[2][kDefaultCoder][r];
    std::printf(
        "  -> fvv 97 arith3 minus openjpeg: %+.2f dB RGB, %+.2f dB Y; decode speed ratio %.2fx\n",
        (f.psnr_rgb - o.psnr_rgb) / f.n, (f.psnr_y - o.psnr_y) / f.n,
        (o.dec_ms / o.n) / (f.dec_ms / f.n));
    const Row& q = rows[2][kQuadtreeCoder][r];
    if (q.n > 0)
      std::printf(
          "  -> fvv 97 arith4 minus openjpeg: %+.2f dB RGB, %+.2f dB Y; decode speed ratio %.2fx\n",
          (q.psnr_rgb - o.psnr_rgb) / q.n, (q.psnr_y - o.psnr_y) / q.n,
          (o.dec_ms / o.n) / (q.dec_ms / q.n));
  }
  return 0;
}

// 8 frames x 8 cameras x 512 x 512: camera c sees the image shifted and scaled by
// 1 + 0.015 c; frame t pans by 3 px per frame. Bilinear resampling.
int Gop4d(const std::string& dir, EntropyCoder coder) {
  auto img = ReadImage(dir + "/kodak/kodim23.png");
  if (!img.ok()) {
    std::fprintf(stderr, "skip: %s\n", img.status().ToString().c_str());
    return 0;
  }
  const Shape4D shape{{8, 8, 512, 512}};
  std::vector<uint8_t> rgb(shape.count() * 3);
  for (uint32_t t = 0; t < 8; ++t)
    for (uint32_t c = 0; c < 8; ++c)
      for (uint32_t y = 0; y < 512; ++y)
        for (uint32_t x = 0; x < 512; ++x) {
          const double scale = 1.0 + 0.015 * c;
          const double sx = 100 + 12.0 * c + 3.0 * t + (x - 256.0) / scale + 256;
          const double sy = 0 + (y - 256.0) / scale + 256 - 2.0 * c;
          const int x0 = std::min<int>(std::max(0.0, std::floor(sx)), img->width - 2);
          const int y0 = std::min<int>(std::max(0.0, std::floor(sy)), img->height - 2);
          const double fx = std::min(1.0, std::max(0.0, sx - x0)),
                       fy = std::min(1.0, std::max(0.0, sy - y0));
          for (int ch = 0; ch < 3; ++ch) {
            auto p = [&](int xx, int yy) {
              return double(img->pixels[(size_t(yy) * img->width + xx) * 3 + ch]);
            };
            const double v = (p(x0, y0) * (1 - fx) + p(x0 + 1, y0) * fx) * (1 - fy) +
                             (p(x0, y0 + 1) * (1 - fx) + p(x0 + 1, y0 + 1) * fx) * fy;
            rgb[(shape.Index(t, c, y, x)) * 3 + ch] = static_cast<uint8_t>(v + 0.5);
          }
        }
  const Block block = BlockFromRgb(rgb.data(), shape, ColourSpace::kYCbCr601, ChromaFormat::k444,
                                   kDefaultSampleFrac);
  ThreadPool pool(2);
  std::printf(
      "4D GOP 8x8x512x512 from kodim23 (shifted/rescaled cameras, panning frames), 9/7 + %s, 2 "
      "threads\n",
      CoderName(coder));
  std::printf("%6s %9s %9s %9s %10s %9s %10s %9s\n", "bpp", "bytes", "RGB dB", "Y dB", "enc MS/s",
              "dec ms", "dec MS/s", "first ms");
  for (double bpp : {0.05, 0.1, 0.25, 0.5}) {
    EncodeSettings s;
    s.rate_value = bpp;
    s.coder = coder;
    s.runner = pool.runner();
    auto t0 = Clock::now();
    auto enc = EncodeBlock(block, nullptr, s);
    const double e = Secs(t0);
    // A player decodes GOP after GOP of one shape and hands each dropped GOP's
    // sample buffers to the next (player/decoder: SamplePool), so the steady
    // state decodes into recycled buffers. The first decode pays for fresh
    // memory (page faults and kernel zeroing of 3 x 64 MiB), shown apart.
    SamplePool samples;
    samples.SetLimit(3);
    DecodeBudget budget;
    budget.sample_pool = &samples;
    double first = 0, best = 1e9;
    Block dec;
    for (int rep = 0; rep < 4; ++rep) {
      for (Plane4D& plane : dec.channels) samples.Give(std::move(plane.samples));
      t0 = Clock::now();
      dec = std::move(DecodeBlock(*enc, budget, pool.runner()).value());
      const double secs = Secs(t0);
      if (rep == 0) {
        first = secs;
      } else {
        best = std::min(best, secs);
      }
    }
    std::vector<uint8_t> out(rgb.size());
    BlockToRgb(dec, out.data());
    std::printf("%6.2f %9llu %9.2f %9.2f %10.1f %9.0f %10.1f %9.0f\n", bpp,
                (unsigned long long)enc->total_bytes(), PsnrRgb(rgb, out), PsnrY(rgb, out),
                shape.count() / e / 1e6, best * 1e3, shape.count() / best / 1e6, first * 1e3);
  }
  rusage ru;
  getrusage(RUSAGE_SELF, &ru);
  std::printf(
      "dec ms: best of 3 decodes into the buffers of the block decoded before (a player's steady "
      "state); first ms: the first decode, into fresh memory. Real time: 8 frames at 25 fps "
      "in under 320 ms\n");
  std::printf("peak memory (whole run, RSS): %.0f MiB\n", ru.ru_maxrss / 1024.0);
  return 0;
}

}  // namespace
}  // namespace fvv

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(
        stderr,
        "usage: codec_bench kodak|gop4d DATA_DIR [--images N] [--only-97-arith] [--coder C]\n"
        "  --only-97-arith  kodak: code with the 9/7 kernel and the arithmetic coders only\n"
        "                   (the pair compared with OpenJPEG)\n"
        "  --coder C        gop4d: arith3 (the default, what fvv encode writes) or arith4\n");
    return 2;
  }
  const std::string mode = argv[1], dir = argv[2];
  int images = 24;
  bool only_97_arith = false;
  fvv::EntropyCoder coder = fvv::EntropyCoder::kSetSignContexts;
  for (int i = 3; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--images" && i + 1 < argc) {
      images = std::max(1, std::min(24, std::atoi(argv[++i])));
    } else if (a == "--only-97-arith") {
      only_97_arith = true;
    } else if (a == "--coder" && i + 1 < argc) {
      const std::string c = argv[++i];
      if (c != "arith3" && c != "arith4") {
        std::fprintf(stderr, "--coder: arith3 or arith4, not %s\n", c.c_str());
        return 2;
      }
      coder = c == "arith4" ? fvv::EntropyCoder::kQuadtree : fvv::EntropyCoder::kSetSignContexts;
    } else {
      std::fprintf(stderr, "unknown option %s\n", a.c_str());
      return 2;
    }
  }
  if (mode == "kodak") return fvv::Kodak(dir, images, only_97_arith);
  if (mode == "gop4d") return fvv::Gop4d(dir, coder);
  std::fprintf(stderr, "unknown mode %s\n", mode.c_str());
  return 2;
}
