// The surface of every frame against a synthetic actor whose surface moves
// apart from its skeleton (loose shorts that flare as the legs swing,
// `fvv synth --garment`): the stream's decoded surface, skinned, lies nearer
// the true surface of each frame than the fitted body does, and the held-out
// view renders better.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "encoder/shape/surface_index.h"
#include "fvv/fvv_decoder.h"
#include "tests/synth_capture_fixture.h"
#include "tools/synth/synth.h"

namespace fvv {
namespace {

constexpr uint32_t kFrames = 8;
// What the surface must buy over the fitted body (the measured figures are in
// the test's output and docs/encoder.md): where the garment stands off the
// fitted body, a shorter distance to the true surface; in the held-out view,
// decibels (mean over the frames).
constexpr double kMaxGarmentDistanceShare = 0.5;
constexpr double kMinGainDb = 0.4;

class GarmentTest : public SynthCaptureFixture<GarmentTest> {
 public:
  static constexpr const char* kName = "garment_test";
  static SynthOptions Options() {
    SynthOptions o;
    o.cameras = 8;
    o.frames = kFrames;
    o.width = 320;
    o.height = 240;
    o.held_out = 2;
    o.garment = 0.08;
    o.link_silhouettes = true;
    return o;
  }
};

// Per frame and true surface vertex, the distance to the stream's surface as
// a player draws it (its own positions when the frame carries them, else the
// model's, skinned with the decoded bones).
std::vector<std::vector<double>> DistanceToTruth(const std::string& stream,
                                                 const std::string& truth_dir) {
  std::vector<std::vector<double>> out;
  fvv_decoder* d = nullptr;
  EXPECT_EQ(fvv_decoder_create(nullptr, &d), FVV_OK);
  EXPECT_EQ(fvv_decoder_open_file(d, stream.c_str()), FVV_OK);
  fvv_model m;
  EXPECT_EQ(fvv_decoder_get_model(d, &m), FVV_OK);
  std::vector<std::array<uint32_t, 3>> triangles(m.triangle_count);
  for (uint32_t t = 0; t < m.triangle_count; ++t) {
    triangles[t] = {m.triangles[3 * t], m.triangles[3 * t + 1], m.triangles[3 * t + 2]};
  }
  for (uint32_t f = 0; f < kFrames; ++f) {
    fvv_frame* frame = nullptr;
    if (fvv_decoder_decode_frame(d, f, nullptr, &frame) != FVV_OK) break;
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
    fvv_frame_release(frame);
    const SurfaceIndex surface(posed, triangles, 0.02);
    char name[48];
    std::snprintf(name, sizeof(name), "/surface_f%06u.bin", f);
    // The synthetic actor's own mesh (its vertex count is its own).
    std::ifstream in(truth_dir + name, std::ios::binary | std::ios::ate);
    const size_t bytes = in ? size_t(in.tellg()) : 0;
    std::vector<float> truth(bytes / 4);
    in.seekg(0);
    in.read(reinterpret_cast<char*>(truth.data()), std::streamsize(truth.size() * 4));
    EXPECT_TRUE(in.good() && truth.size() >= 3) << name;
    std::vector<double> dist(truth.size() / 3);
    for (size_t v = 0; v < dist.size(); ++v) {
      dist[v] = surface.Nearest(Eigen::Vector3d(truth[3 * v], truth[3 * v + 1], truth[3 * v + 2]));
    }
    out.push_back(std::move(dist));
  }
  fvv_decoder_destroy(d);
  return out;
}

TEST_F(GarmentTest, TheSurfaceOfEveryFrameFollowsTheGarmentAndRendersBetter) {
  EncoderSettings with_surface = TruePoses();  // true poses: this measures the surface
  with_surface.surface = true;
  auto plain = Encode("plain.fvv", TruePoses());
  ASSERT_TRUE(plain.ok()) << plain.status().ToString();
  auto surfaced = Encode("surface.fvv", with_surface);
  ASSERT_TRUE(surfaced.ok()) << surfaced.status().ToString();
  const std::string truth = synth_.output_dir + "/truth";
  const auto a = DistanceToTruth(dir_ + "/plain.fvv", truth);
  const auto b = DistanceToTruth(dir_ + "/surface.fvv", truth);
  ASSERT_EQ(a.size(), kFrames);
  ASSERT_EQ(b.size(), kFrames);
  // Over the whole body, and where the garment stands off the fitted body
  // (true vertices more than 1 cm from it).
  double all_a = 0, all_b = 0, off_a = 0, off_b = 0, psnr_a = 0, psnr_b = 0;
  size_t all = 0, off = 0;
  for (uint32_t f = 0; f < kFrames; ++f) {
    ASSERT_EQ(a[f].size(), b[f].size());
    double fa = 0, fb = 0, ga = 0, gb = 0;
    size_t garment = 0;
    for (size_t v = 0; v < a[f].size(); ++v) {
      fa += a[f][v], fb += b[f][v];
      if (a[f][v] > 0.01) ga += a[f][v], gb += b[f][v], ++garment;
    }
    all_a += fa, all_b += fb, all += a[f].size();
    off_a += ga, off_b += gb, off += garment;
    const StatusOr<double> pa = HeldOutPsnr("plain.fvv", f);
    const StatusOr<double> pb = HeldOutPsnr("surface.fvv", f);
    ASSERT_TRUE(pa.ok() && pb.ok());
    std::printf(
        "  frame %u: true surface to the stream's, fitted body / surface: %.2f / %.2f mm, "
        "where the garment stands off (%zu vertices) %.2f / %.2f mm; held-out Renderer II "
        "%.2f / %.2f dB\n",
        f, 1000 * fa / a[f].size(), 1000 * fb / a[f].size(), garment,
        garment ? 1000 * ga / garment : 0.0, garment ? 1000 * gb / garment : 0.0, *pa, *pb);
    psnr_a += *pa / kFrames, psnr_b += *pb / kFrames;
  }
  ASSERT_GT(off, 0u);
  std::printf(
      "  mean: %.2f / %.2f mm, where the garment stands off %.2f / %.2f mm; %.2f / %.2f dB; "
      "bytes %llu / %llu (surface %llu)\n",
      1000 * all_a / all, 1000 * all_b / all, 1000 * off_a / off, 1000 * off_b / off, psnr_a,
      psnr_b, (unsigned long long)plain->file_bytes, (unsigned long long)surfaced->file_bytes,
      (unsigned long long)surfaced->surface_bytes);
  EXPECT_LT(off_b / off, kMaxGarmentDistanceShare * (off_a / off));
  EXPECT_GT(psnr_b, psnr_a + kMinGainDb);
}

}  // namespace
}  // namespace fvv
