// Motion-track benchmark: kbps at 25 fps on real motion capture (the CMU BVH
// files in Debian's assimp-testmodels), for the fvv motion coder against raw
// floats and zstd -19 of raw floats, measured in the same run.
//
//   build/bench/motion_bench [FILE.bvh[:unit_metres] ...]
// Without arguments it runs the three BVH files of assimp-testmodels.
#include <zstd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
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
size_t CodeSequence(const Skeleton& sk, const MotionParams& p, const std::vector<QuantisedPose>& q,
                    double* max_rot_err_deg, const std::vector<std::vector<double>>& truth,
                    double* ms) {
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
          *max_rot_err_deg =
              std::max(*max_rot_err_deg, std::fabs(back[d] - truth[f0 + i][d]) * 180 / M_PI);
        }
      }
    }
  }
  *ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return bytes;
}

// The product's generic body has 35 DOF: 6 at the root, 3 per ball joint, 1 per
// hinge, 2 per wrist, ankle and neck. Real motion mapped onto that layout (per
// joint, the channels that move most) measures the rate of a "full-body skeleton"
// as the product defines it.
struct BodyJoint {
  const char* names[2];  // CMU, and the Boxing_Toes skeleton's name
  int keep;
};
const BodyJoint kBody35[] = {
    {{"Hips", "Hips"}, 6},
    {{"LowerBack", "Ab"}, 3},
    {{"Neck", "Neck"}, 2},
    {{"LeftArm", "LeftShoulder"}, 3},
    {{"LeftForeArm", "LeftElbow"}, 1},
    {{"LeftHand", "LeftWrist"}, 2},
    {{"RightArm", "RightShoulder"}, 3},
    {{"RightForeArm", "RightElbow"}, 1},
    {{"RightHand", "RightWrist"}, 2},
    {{"LeftUpLeg", "LeftHip"}, 3},
    {{"LeftLeg", "LeftKnee"}, 1},
    {{"LeftFoot", "LeftAnkle"}, 2},
    {{"RightUpLeg", "RightHip"}, 3},
    {{"RightLeg", "RightKnee"}, 1},
    {{"RightFoot", "RightAnkle"}, 2},
};

// Reduces skeleton and frames to the 35-DOF layout; false if joints are missing.
bool ToBody35(Skeleton* sk, std::vector<std::vector<double>>* frames) {
  const std::vector<DofRef> dofs = sk->Dofs();
  std::vector<bool> keep(dofs.size(), false);
  int kept = 0;
  for (const BodyJoint& j : kBody35) {
    int bone = -1;
    for (size_t b = 0; b < sk->bones.size(); ++b) {
      if (sk->bones[b].name == j.names[0] || sk->bones[b].name == j.names[1]) bone = int(b);
    }
    if (bone < 0) return false;
    std::vector<std::pair<double, size_t>> var;
    for (size_t d = 0; d < dofs.size(); ++d) {
      if (dofs[d].bone != bone) continue;
      double mean = 0, sq = 0;
      for (const auto& f : *frames) mean += f[d];
      mean /= frames->size();
      for (const auto& f : *frames) sq += (f[d] - mean) * (f[d] - mean);
      var.push_back({dofs[d].kind >= 3 ? 1e30 : sq, d});  // root translation always kept
    }
    std::sort(var.rbegin(), var.rend());
    for (int k = 0; k < j.keep && k < int(var.size()); ++k, ++kept) keep[var[k].second] = true;
  }
  for (Bone& b : sk->bones) b.dof_mask = 0;
  for (size_t d = 0; d < dofs.size(); ++d) {
    if (keep[d]) sk->bones[dofs[d].bone].dof_mask |= uint8_t(1u << dofs[d].kind);
  }
  for (auto& f : *frames) {
    std::vector<double> r;
    for (size_t d = 0; d < dofs.size(); ++d) {
      if (keep[d]) r.push_back(f[d]);
    }
    f = std::move(r);
  }
  return kept == 35;
}

bool Report(const std::string& label, const Skeleton& sk,
            const std::vector<std::vector<double>>& frames) {
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
  constexpr int kModes = 5;
  double kbps[kModes] = {}, err = 0, ms = 0;
  const struct {
    MotionCoder coder;
    uint16_t key_interval;
    uint32_t rotation_step;
  } modes[kModes] = {{MotionCoder::kArith, 1, 596523},
                     {MotionCoder::kZstd, 1, 596523},
                     {MotionCoder::kArith, 1, 1193046},
                     {MotionCoder::kArith, 2, 596523},
                     {MotionCoder::kArith, 4, 596523}};
  for (int m = 0; m < kModes; ++m) {
    MotionParams p;
    p.coder = modes[m].coder;
    p.key_interval = modes[m].key_interval;
    p.rotation_step = modes[m].rotation_step;
    std::vector<QuantisedPose> q;
    for (const auto& f : frames) q.push_back(QuantisePose(dofs, p, f));
    if (std::getenv("FVV_NO_TRAIN") == nullptr) TrainMotionParams(sk, q, kGopFrames, &p);
    double e = 0, t = 0;
    // The 'mtrk' box (with its statistics) is sent once; count it in.
    const size_t bytes = CodeSequence(sk, p, q, &e, frames, &t) + WriteMotionParamsBox(p).size();
    if (bytes == 0) {
      std::fprintf(stderr, "motion_bench: %s: round trip failed\n", label.c_str());
      return false;
    }
    kbps[m] = bytes * 8 / seconds / 1000;
    if (m == 0 && std::getenv("FVV_VERBOSE")) {
      std::fprintf(stderr, "%s: mtrk box %zu bytes, %zu context initialisers\n", label.c_str(),
                   WriteMotionParamsBox(p).size(), p.context_init.size());
    }
    if (m == 0) {
      err = e;
      ms = t / seconds;
    }
  }
  std::printf("%-22s %6zu %5zu %6zu | %8.1f %8.2f | %8.2f %8.2f %8.2f %8.2f %8.2f | %7.4f %6.2f\n",
              label.c_str(), frames.size(), dofs.size(), moving, raw_kbps, zstd_kbps, kbps[0],
              kbps[1], kbps[2], kbps[3], kbps[4], err, ms);
  return true;
}

int Run(std::vector<Input> inputs) {
  if (inputs.empty()) {
    const std::string dir = "/usr/share/assimp/models/BVH/";
    inputs = {{dir + "01_01.bvh", 0.0254 / 0.45},
              {dir + "01_03.bvh", 0.0254 / 0.45},
              {dir + "Boxing_Toes.bvh", 0.01}};
  }
  std::printf(
      "motion track at %.0f fps, GOP %u frames (a key frame each), default steps "
      "0.05 deg / 0.5 mm\n",
      kFps, kGopFrames);
  std::printf("%-22s %6s %5s %6s | %8s %8s | %8s %8s %8s %8s %8s | %7s %6s\n", "motion", "frames",
              "DOF", "moving", "raw f32", "zstd f32", "arith", "zstd", "arith", "arith k2",
              "arith k4", "max err", "codec");
  std::printf("%-22s %6s %5s %6s | %8s %8s | %8s %8s %8s %8s %8s | %7s %6s\n", "", "", "", "",
              "kbps", "kbps", "kbps", "kbps", "0.1deg", "kbps", "kbps", "deg", "ms/s");
  for (const Input& in : inputs) {
    auto motion = ReadBvhFile(in.path, in.unit);
    if (!motion.ok()) {
      std::fprintf(stderr, "motion_bench: %s (install assimp-testmodels: tools/setup.sh)\n",
                   motion.status().ToString().c_str());
      return 1;
    }
    const char* slash = std::strrchr(in.path.c_str(), '/');
    const std::string name = slash ? slash + 1 : in.path;
    const auto all_frames = ResampleMotion(*motion, kFps);
    if (!Report(name + " all", motion->skeleton, all_frames)) return 1;
    Skeleton body = motion->skeleton;
    auto body_frames = all_frames;
    if (ToBody35(&body, &body_frames) && !Report(name + " 35-DOF", body, body_frames)) return 1;
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
