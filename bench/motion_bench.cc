// Motion-track benchmark: kbps at 25 fps on real motion capture (the CMU BVH
// files in Debian's assimp-testmodels), for the fvv motion coder against raw
// floats and zstd -19 of raw floats, measured in the same run.
//
//   build/bench/motion_bench [FILE.bvh[:unit_metres] ...]
// Without arguments it runs the three BVH files of assimp-testmodels.
#include <zstd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "container/motion_track.h"
#include "encoder/import/bvh.h"

namespace fvv {
namespace {

constexpr double kFps = 25;
constexpr uint32_t kGopFrames = 8;

struct Input {
  std::string path;
  double unit;
};

size_t ZstdSize(const void* data, size_t size) {
  std::vector<uint8_t> out(ZSTD_compressBound(size));
  const size_t n = ZSTD_compress(out.data(), out.size(), data, size, 19);
  return ZSTD_isError(n) ? 0 : n;
}

// Codes the whole sequence as GOP fragments; returns total bytes, or 0 on failure.
size_t CodeSequence(const Skeleton& sk, const MotionParams& p,
                    const std::vector<QuantisedPose>& q, double* max_rot_err_deg,
                    const std::vector<std::vector<double>>& truth, double* ms) {
  size_t bytes = 0;
  const auto dofs = sk.Dofs();
  const auto start = std::chrono::steady_clock::now();
  for (size_t f0 = 0; f0 < q.size(); f0 += kGopFrames) {
    const size_t n = std::min<size_t>(kGopFrames, q.size() - f0);
    std::vector<QuantisedPose> gop(q.begin() + f0, q.begin() + f0 + n);
    auto payload = EncodeMotion(sk, p, gop);
    if (!payload.ok()) return 0;
    bytes += payload->size() + 12;  // with its box header
    BoxHeader h;
    h.type = box::kMotion;
    h.header_size = 12;
    h.size = payload->size() + 12;
    std::vector<DecodedFrame> frames;
    if (!DecodeMotion(h, payload->data(), sk, p, static_cast<uint32_t>(n), &frames).ok()) return 0;
    for (size_t i = 0; i < n; ++i) {
      if (!frames[i].coded) continue;
      if (frames[i].values != gop[i]) return 0;
      const auto back = DequantisePose(dofs, p, frames[i].values);
      for (size_t d = 0; d < dofs.size(); ++d) {
        if (IsRotationDof(dofs[d].kind)) {
          *max_rot_err_deg = std::max(*max_rot_err_deg, std::fabs(back[d] - truth[f0 + i][d]) * 180 / M_PI);
        }
      }
    }
  }
  *ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return bytes;
}

int Run(std::vector<Input> inputs) {
  if (inputs.empty()) {
    const std::string dir = "/usr/share/assimp/models/BVH/";
    inputs = {{dir + "01_01.bvh", 0.0254 / 0.45}, {dir + "01_03.bvh", 0.0254 / 0.45},
              {dir + "Boxing_Toes.bvh", 0.01}};
  }
  std::printf("motion track at %.0f fps, GOP %u frames (a key frame each), default steps "
              "0.05 deg / 0.5 mm\n", kFps, kGopFrames);
  std::printf("%-16s %6s %5s %6s | %9s %9s | %9s %9s %9s %9s | %8s %7s\n", "file", "frames", "DOF",
              "moving", "raw f32", "zstd f32", "fvv arith", "fvv zstd", "arith k2", "arith k4",
              "max err", "enc+dec");
  std::printf("%-16s %6s %5s %6s | %9s %9s | %9s %9s %9s %9s | %8s %7s\n", "", "", "", "", "kbps",
              "kbps", "kbps", "kbps", "kbps", "kbps", "deg", "ms/s");
  for (const Input& in : inputs) {
    auto motion = ReadBvhFile(in.path, in.unit);
    if (!motion.ok()) {
      std::fprintf(stderr, "motion_bench: %s (install assimp-testmodels: tools/setup.sh)\n",
                   motion.status().ToString().c_str());
      return 1;
    }
    const Skeleton& sk = motion->skeleton;
    const auto frames = ResampleMotion(*motion, kFps);
    const auto dofs = sk.Dofs();
    const double seconds = frames.size() / kFps;
    size_t moving = 0;
    for (size_t d = 0; d < dofs.size(); ++d) {
      for (const auto& f : frames) {
        if (f[d] != frames[0][d]) {
          ++moving;
          break;
        }
      }
    }
    std::vector<float> raw;
    for (const auto& f : frames)
      for (double v : f) raw.push_back(static_cast<float>(v));
    const double raw_kbps = raw.size() * 32 / seconds / 1000;
    const double zstd_kbps = ZstdSize(raw.data(), raw.size() * 4) * 8 / seconds / 1000;
    double kbps[4] = {0, 0, 0, 0}, err = 0, ms = 0;
    const struct {
      MotionCoder coder;
      uint16_t key_interval;
    } modes[4] = {{MotionCoder::kArith, 1}, {MotionCoder::kZstd, 1}, {MotionCoder::kArith, 2},
                  {MotionCoder::kArith, 4}};
    for (int m = 0; m < 4; ++m) {
      MotionParams p;
      p.coder = modes[m].coder;
      p.key_interval = modes[m].key_interval;
      std::vector<QuantisedPose> q;
      for (const auto& f : frames) q.push_back(QuantisePose(dofs, p, f));
      double e = 0, t = 0;
      const size_t bytes = CodeSequence(sk, p, q, &e, frames, &t);
      if (bytes == 0) {
        std::fprintf(stderr, "motion_bench: %s: round trip failed\n", in.path.c_str());
        return 1;
      }
      kbps[m] = bytes * 8 / seconds / 1000;
      if (m == 0) {
        err = e;
        ms = t / seconds;
      }
    }
    const char* name = std::strrchr(in.path.c_str(), '/');
    std::printf("%-16s %6zu %5zu %6zu | %9.1f %9.2f | %9.2f %9.2f %9.2f %9.2f | %8.4f %7.2f\n",
                name ? name + 1 : in.path.c_str(), frames.size(), dofs.size(), moving, raw_kbps,
                zstd_kbps, kbps[0], kbps[1], kbps[2], kbps[3], err, ms);
  }
  return 0;
}

}  // namespace
}  // namespace fvv

int main(int argc, char** argv) {
  std::vector<fvv::Input> inputs;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "-h" || a == "--help") {
      std::printf("usage: %s [FILE.bvh[:unit_metres] ...]\n", argv[0]);
      return 0;
    }
    double unit = 0.01;
    const size_t colon = a.rfind(':');
    if (colon != std::string::npos) {
      unit = std::atof(a.c_str() + colon + 1);
      a.resize(colon);
    }
    inputs.push_back({a, unit});
  }
  return fvv::Run(inputs);
}
