// The encoder: atlas texel mapping, multi-view resampling checked
// against a synthetic actor's known surface texture, the encode -> decode round
// trip reaching the PSNR the encoder reports, and bad inputs refused with
// errors that name them.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <fstream>

#include "encoder/atlas/atlas.h"
#include "encoder/body/body_shape_json.h"
#include "encoder/body/generic_body.h"
#include "encoder/encode/encoder.h"
#include "encoder/encode/pose_file.h"
#include "encoder/encode/resample.h"
#include "fvv/fvv_decoder.hpp"
#include "fvv/fvv_encoder.hpp"
#include "tools/synth/synth.h"

namespace fvv {
namespace {

// The body shape a pose file carries comes back as written (the encoder
// rebuilds the body the poses were fitted with), files from before the neck
// ratio load with the neck following the head, and bad shapes are refused
// with errors that name the field.
TEST(PoseFile, BodyShapeRoundTripsAndBadShapesAreRefused) {
  BodyShape shape;
  shape.stature = 0.7;
  shape.length[kSegHead] = 1.6;
  shape.girth[kSegHead] = 2.9;
  shape.girth[kSegLeftThigh] = 1.2;
  shape.neck_ratio = 0.45;
  auto file = [&](const nlohmann::json& body_shape) {
    nlohmann::json j;
    j["dof_names"] = GenericDofNames();
    j["body_shape"] = body_shape;
    j["frames"] = {{{"frame", 3}, {"dofs", std::vector<double>(kGenericDofCount, 0.0)}}};
    return ParsePoseFile(j.dump(), "poses.json");
  };
  StatusOr<PoseSequence> back = file(BodyShapeToJson(shape));
  ASSERT_TRUE(back.ok()) << back.status().ToString();
  EXPECT_EQ(back->shape.stature, shape.stature);
  EXPECT_EQ(back->shape.length, shape.length);
  EXPECT_EQ(back->shape.girth, shape.girth);
  EXPECT_EQ(back->shape.neck_ratio, shape.neck_ratio);
  EXPECT_EQ(back->first_frame, 3u);

  nlohmann::json old = BodyShapeToJson(shape);
  old.erase("neck_ratio");
  back = file(old);
  ASSERT_TRUE(back.ok()) << back.status().ToString();
  EXPECT_EQ(back->shape.neck_ratio, 1.0);

  const std::vector<std::pair<std::string, nlohmann::json>> bad = {
      {"neck ratio",
       [&] {
         nlohmann::json j = BodyShapeToJson(shape);
         j["neck_ratio"] = 0.1;
         return j;
       }()},
      {"neck_ratio",
       [&] {
         nlohmann::json j = BodyShapeToJson(shape);
         j["neck_ratio"] = "thin";
         return j;
       }()},
      {"length",
       [&] {
         nlohmann::json j = BodyShapeToJson(shape);
         j["length"].erase(0);
         return j;
       }()},
      {"stature",
       [&] {
         nlohmann::json j = BodyShapeToJson(shape);
         j.erase("stature");
         return j;
       }()},
      {"head",
       [&] {
         nlohmann::json j = BodyShapeToJson(shape);
         j["girth"][kSegHead] = 3.5;
         return j;
       }()},
      {"body_shape", nlohmann::json(7)}};
  for (const auto& [name, j] : bad) {
    const StatusOr<PoseSequence> r = file(j);
    ASSERT_FALSE(r.ok()) << name;
    EXPECT_NE(r.status().message().find(name), std::string::npos) << r.status().message();
  }
}

TEST(TexelMap, CoversEveryTexelCentreInsideATriangleWithValidWeights) {
  const BodyModel body = MakeGenericBody(BodyShape(), MeshResolution{10, 12});
  AtlasOptions ao;
  ao.size = 128;
  StatusOr<Atlas> atlas = BuildAtlas(body.mesh, ao);
  ASSERT_TRUE(atlas.ok()) << atlas.status().ToString();
  const TexelMap strict = MapAtlasTexels(atlas->mesh, 128, 0.0);
  const TexelMap grown = MapAtlasTexels(atlas->mesh, 128, 1.0);
  ASSERT_FALSE(strict.texel.empty());
  // Dilation adds a ring of texels around the charts, and keeps every strict one.
  EXPECT_GT(grown.texel.size(), strict.texel.size() * 11 / 10);
  std::vector<uint8_t> in_grown(128 * 128, 0);
  for (uint32_t t : grown.texel) in_grown[t] = 1;
  for (uint32_t t : strict.texel) ASSERT_TRUE(in_grown[t]);
  // Weights are barycentric (non-negative, summing to 1) and the weighted UV
  // lies within a texel of the texel's centre (within half a texel diagonal
  // for texels inside a triangle).
  for (const TexelMap* map : {&strict, &grown}) {
    for (size_t e = 0; e < map->texel.size(); ++e) {
      const auto& w = map->weights[e];
      ASSERT_NEAR(w[0] + w[1] + w[2], 1.0f, 1e-4f);
      ASSERT_GE(std::min({w[0], w[1], w[2]}), -1e-5f);
      const auto& tri = atlas->mesh.triangles[map->triangle[e]];
      double u = 0, v = 0;
      for (int k = 0; k < 3; ++k) {
        u += w[k] * atlas->mesh.uvs[tri[k]][0] * 128;
        v += w[k] * atlas->mesh.uvs[tri[k]][1] * 128;
      }
      const double cx = map->texel[e] % 128 + 0.5, cy = map->texel[e] / 128 + 0.5;
      ASSERT_LE(std::hypot(u - cx, v - cy), map == &strict ? 1e-3 : 1.0 + 1e-3);
    }
  }
}

// A small unlit, noise-free synthetic capture shared by the tests below.
class EncodeTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = ::testing::TempDir() + "/encode_test_" + std::to_string(getpid());
    std::system(("rm -rf '" + dir_ + "'").c_str());
    SynthOptions o;
    o.output_dir = dir_ + "/cap";
    o.cameras = 6;
    o.frames = 3;
    o.held_out = 0;
    o.noise = 0;
    o.unlit = true;
    o.seed = 5;
    synth_ = RunSynth(o).status();
  }
  static void TearDownTestSuite() { std::system(("rm -rf '" + dir_ + "'").c_str()); }
  void SetUp() override { ASSERT_TRUE(synth_.ok()) << synth_.ToString(); }

  static EncoderSettings Settings() {
    EncoderSettings s;
    s.poses = dir_ + "/cap";  // the generator's true poses: resampling on its own
    s.atlas_size = 256;
    s.gop_frames = 2;   // two time spans: a full one and a short one
    s.gop_cameras = 4;  // two camera groups: 4 and 2 cameras
    return s;
  }

  static void RoundTrip(EncoderSettings s, const std::string& name, uint32_t gops);

  static std::string dir_;
  static Status synth_;
};
std::string EncodeTest::dir_;
Status EncodeTest::synth_;

// Bilinear sample of an RGB image at texture coordinates (u, v) in [0, 1].
std::array<double, 3> SampleTexture(const Image& t, double u, double v) {
  const double x = std::clamp(u * t.width - 0.5, 0.0, t.width - 1.0);
  const double y = std::clamp(v * t.height - 0.5, 0.0, t.height - 1.0);
  const int x0 = std::min(int(x), int(t.width) - 2), y0 = std::min(int(y), int(t.height) - 2);
  const double fx = x - x0, fy = y - y0;
  std::array<double, 3> out;
  for (int k = 0; k < 3; ++k) {
    auto p = [&](int xx, int yy) { return double(t.pixels[(size_t(yy) * t.width + xx) * 3 + k]); };
    out[k] = (1 - fy) * ((1 - fx) * p(x0, y0) + fx * p(x0 + 1, y0)) +
             fy * ((1 - fx) * p(x0, y0 + 1) + fx * p(x0 + 1, y0 + 1));
  }
  return out;
}

// Barycentric coordinates of texel-space point (x, y) in an atlas triangle
// (extrapolated outside it).
std::array<double, 3> Barycentric(const Atlas& atlas, const std::array<uint32_t, 3>& tri, int size,
                                  double x, double y) {
  double px[3], py[3];
  for (int k = 0; k < 3; ++k)
    px[k] = atlas.mesh.uvs[tri[k]][0] * size, py[k] = atlas.mesh.uvs[tri[k]][1] * size;
  const double d = (px[1] - px[0]) * (py[2] - py[0]) - (py[1] - py[0]) * (px[2] - px[0]);
  const double b1 = ((x - px[0]) * (py[2] - py[0]) - (y - py[0]) * (px[2] - px[0])) / d;
  const double b2 = ((px[1] - px[0]) * (y - py[0]) - (py[1] - py[0]) * (x - px[0])) / d;
  return {1 - b1 - b2, b1, b2};
}

TEST_F(EncodeTest, ResampledTexturesMatchTheActorsSurfaceTexture) {
  EncoderSettings s = Settings();
  s.save_textures = dir_ + "/tex";
  StatusOr<EncodeSummary> sum = EncodeCapture(dir_ + "/cap", dir_ + "/a.fvv", s);
  ASSERT_TRUE(sum.ok()) << sum.status().ToString();

  // Where each atlas texel lies in the actor's own texture: the built-in
  // body's chart UVs, through the atlas vertex -> source vertex map.
  StatusOr<PoseSequence> poses = LoadPoseFile(dir_ + "/cap");
  ASSERT_TRUE(poses.ok());
  const BodyModel body = MakeGenericBody(poses->shape);
  AtlasOptions ao;
  ao.size = 256;
  StatusOr<Atlas> atlas = BuildAtlas(body.mesh, ao);
  ASSERT_TRUE(atlas.ok());
  const TexelMap map = MapAtlasTexels(atlas->mesh, 256);
  StatusOr<Image> truth = ReadImage(dir_ + "/cap/truth/texture.png");
  ASSERT_TRUE(truth.ok()) << truth.status().ToString();

  double abs_sum = 0, shifted_sum = 0;
  std::vector<double> errs, control;
  size_t seen = 0, within = 0;
  StatusOr<Capture> cap = LoadCapture(dir_ + "/cap");
  ASSERT_TRUE(cap.ok());
  for (uint32_t f = 0; f < 3; ++f) {
    for (const CaptureCamera& camera : cap->cameras) {
      const std::string name = camera.calibration.name;
      StatusOr<Image> tex = ReadImage(TexturePath(dir_ + "/tex", name, f));
      StatusOr<Image> mask = ReadImage(TextureMaskPath(dir_ + "/tex", name, f));
      ASSERT_TRUE(tex.ok() && mask.ok()) << name << " frame " << f;
      size_t camera_seen = 0;
      for (size_t e = 0; e < map.texel.size(); ++e) {
        const uint32_t t = map.texel[e];
        if (!mask->pixels[t]) continue;
        // The truth texture averaged over the texel's footprint (4x4 points):
        // the atlas texel integrates the surface much as a camera pixel does.
        const auto& tri = atlas->mesh.triangles[map.triangle[e]];
        const double cx = t % 256 + 0.5, cy = t / 256 + 0.5;
        std::array<double, 3> want{0, 0, 0};
        double u = 0, v = 0;
        for (int sy = 0; sy < 4; ++sy) {
          for (int sx = 0; sx < 4; ++sx) {
            const auto w = Barycentric(*atlas, tri, 256, cx + (sx - 1.5) / 4, cy + (sy - 1.5) / 4);
            double su = 0, sv = 0;
            for (int k = 0; k < 3; ++k) {
              const auto& uv = body.mesh.uvs[atlas->source_vertex[tri[k]]];
              su += w[k] * uv[0];
              sv += w[k] * uv[1];
            }
            const auto p = SampleTexture(*truth, su, sv);
            for (int k = 0; k < 3; ++k) want[k] += p[k] / 16;
            u += su / 16, v += sv / 16;
          }
        }
        // A control: the same texel compared with a point 3 texels away in the
        // truth texture (what a misplaced sample would give).
        const auto shifted = SampleTexture(*truth, u + 3.0 / truth->width, v + 3.0 / truth->height);
        double d = 0, ds = 0;
        for (int k = 0; k < 3; ++k) {
          d += std::abs(want[k] - tex->pixels[t * 3 + k]);
          ds += std::abs(shifted[k] - tex->pixels[t * 3 + k]);
        }
        abs_sum += d / 3, shifted_sum += ds / 3;
        errs.push_back(d / 3);
        control.push_back(ds / 3);
        within += d / 3 <= 12;
        ++seen, ++camera_seen;
      }
      // Each ring camera sees a good part of the actor.
      EXPECT_GT(camera_seen, map.texel.size() / 6) << name << " frame " << f;
    }
  }
  ASSERT_GT(seen, 0u);

  const double mean = abs_sum / seen, shifted_mean = shifted_sum / seen;
  std::sort(errs.begin(), errs.end());
  std::sort(control.begin(), control.end());
  const double median = errs[errs.size() / 2], p75 = errs[errs.size() * 3 / 4];
  const double control_p75 = control[control.size() * 3 / 4];
  std::printf(
      "  %zu visible texels: |error| mean %.2f, median %.2f, 75th percentile %.2f levels "
      "(%.1f %% within 12); control: mean %.2f, 75th percentile %.2f\n",
      seen, mean, median, p75, 100.0 * within / seen, shifted_mean, control_p75);
  // Most texels match to a couple of levels; the rest lie on sharp edges of
  // the clothing pattern (stripes, seams) and at grazing views, where a camera
  // pixel and an atlas texel integrate the surface differently.
  EXPECT_LT(median, 3.0);
  EXPECT_LT(p75, 8.0);
  EXPECT_LT(mean, 12.0);
  EXPECT_GT(double(within) / seen, 0.75);
  // The same comparison a centimetre off is clearly worse: it can tell a
  // misplaced texture.
  EXPECT_GT(control_p75, 1.5 * p75);
}

// Encodes with `s`, then decodes through the public decoder API and checks
// the decoded RGB against the textures the encoder saved before coding.
void EncodeTest::RoundTrip(EncoderSettings s, const std::string& name, uint32_t gops) {
  const std::string rt = dir_ + "/" + name;
  s.save_textures = rt;
  s.rate_mode = RateMode::kBitsPerSample;
  s.rate_value = 0.3;
  StatusOr<EncodeSummary> sum = EncodeCapture(dir_ + "/cap", rt + ".fvv", s);
  ASSERT_TRUE(sum.ok()) << sum.status().ToString();
  EXPECT_EQ(sum->frames, 3u);
  EXPECT_EQ(sum->cameras, 6u);
  EXPECT_EQ(sum->gops, gops);
  EXPECT_GT(sum->psnr_rgb, 25);
  EXPECT_LT(sum->psnr_rgb, 60);

  // An independent decode through the public decoder API, against the
  // textures the encoder saved before coding.
  fvv::DecoderPtr dec = fvv::MakeDecoder();
  ASSERT_TRUE(dec);
  ASSERT_EQ(fvv_decoder_open_file(dec.get(), (rt + ".fvv").c_str()), FVV_OK)
      << fvv_decoder_error(dec.get());
  StatusOr<Capture> cap = LoadCapture(dir_ + "/cap");
  ASSERT_TRUE(cap.ok());
  double sse = 0;
  uint64_t visible = 0;
  for (uint32_t f = 0; f < 3; ++f) {
    fvv::FramePtr frame = fvv::DecodeFrame(dec.get(), f, nullptr);
    ASSERT_TRUE(frame) << fvv_decoder_error(dec.get());
    ASSERT_EQ(frame->camera_count, 6u);
    ASSERT_EQ(frame->width, 256u);
    for (uint32_t c = 0; c < 6; ++c) {
      const std::string camera = cap->cameras[c].calibration.name;
      StatusOr<Image> tex = ReadImage(TexturePath(rt, camera, f));
      StatusOr<Image> mask = ReadImage(TextureMaskPath(rt, camera, f));
      ASSERT_TRUE(tex.ok() && mask.ok());
      const fvv_view& view = frame->views[c];
      ASSERT_EQ(view.mask != nullptr, s.masks);
      for (size_t i = 0; i < size_t(256) * 256; ++i) {
        const bool seen = mask->pixels[i] == kSeenTexel;
        // The decoded masks are the encoder's, exactly (lossless).
        if (view.mask) {
          ASSERT_EQ(view.mask[i] != 0, seen) << camera << " frame " << f;
        }
        if (!seen) continue;
        ++visible;
        for (int k = 0; k < 3; ++k) {
          const double d = double(view.pixels[i * 3 + k]) - tex->pixels[i * 3 + k];
          sse += d * d;
        }
      }
    }
  }
  EXPECT_EQ(visible, sum->visible_texels);
  const double psnr = 10 * std::log10(255.0 * 255.0 / (sse / (3.0 * visible)));
  std::printf("  decoded RGB PSNR %.3f dB, encoder reported %.3f dB, %.1f:1 vs visible texels\n",
              psnr, sum->psnr_rgb, sum->ratio_visible());
  EXPECT_NEAR(psnr, sum->psnr_rgb, 0.01);
}

TEST_F(EncodeTest, RoundTripReachesTheReportedPsnr) {
  RoundTrip(Settings(), "rt", 4);  // 2 time spans x 2 camera groups
}

TEST_F(EncodeTest, RoundTripWithMasksReachesTheReportedPsnr) {
  EncoderSettings s = Settings();
  s.masks = true;
  RoundTrip(s, "rt_masks", 4);
}

// The predictive texture codec ('ptex'): every camera in one GOP by default.
TEST_F(EncodeTest, PredictiveRoundTripReachesTheReportedPsnr) {
  EncoderSettings s = Settings();
  s.texture_codec = TextureCodec::kPredictive;
  s.kernel = WaveletKernel::kLeGall53;
  s.gop_cameras = 0;
  s.masks = true;                    // its supports
  RoundTrip(s, "rt_predictive", 2);  // 2 time spans x 1 camera group
}

TEST_F(EncodeTest, EncodesAgainFromSavedTexturesToTheSameStream) {
  EncoderSettings s = Settings();
  s.save_textures = dir_ + "/again";
  StatusOr<EncodeSummary> a = EncodeCapture(dir_ + "/cap", dir_ + "/first.fvv", s);
  ASSERT_TRUE(a.ok()) << a.status().ToString();
  EncoderSettings t = Settings();
  t.poses.clear();
  t.textures = dir_ + "/again";
  StatusOr<EncodeSummary> b = EncodeCapture(dir_ + "/cap", dir_ + "/second.fvv", t);
  ASSERT_TRUE(b.ok()) << b.status().ToString();
  EXPECT_EQ(a->texture_bytes, b->texture_bytes);
  EXPECT_EQ(a->mask_bytes, b->mask_bytes);
  EXPECT_EQ(a->motion_bytes, b->motion_bytes);
  EXPECT_DOUBLE_EQ(a->psnr_rgb, b->psnr_rgb);
}

// A camera's colour gain (capture.json) scales what the encoder resamples
// from it, and nothing else: the textures of the same capture without the
// gain, times the gain.
TEST_F(EncodeTest, TexturesReadTheCamerasThroughTheirColourGain) {
  StatusOr<Capture> cap = LoadCapture(dir_ + "/cap");
  ASSERT_TRUE(cap.ok());
  Capture gained = *cap;
  gained.directory = dir_ + "/gained";
  ASSERT_EQ(std::system(("mkdir -p '" + gained.directory + "'").c_str()), 0);
  for (CaptureCamera& c : gained.cameras) {
    c.frames.path = dir_ + "/cap/" + c.frames.path;
    if (c.background) c.background = dir_ + "/cap/" + *c.background;
    if (c.silhouettes) c.silhouettes->path = dir_ + "/cap/" + c.silhouettes->path;
  }
  const std::array<double, 3> gain{0.8, 1.0, 1.25};
  gained.cameras[1].colour_gain = gain;
  ASSERT_TRUE(SaveCapture(gained).ok());
  EncoderSettings s = Settings();
  s.gop_frames = 1;
  // Texels a camera saw only: a twin's colour (the mirror fill) is the
  // cameras' blend, where each camera's gain scales its own share.
  s.mirror_fill = false;
  s.save_textures = dir_ + "/plain_textures";
  ASSERT_TRUE(EncodeCapture(dir_ + "/cap", dir_ + "/plain.fvv", s).ok());
  s.save_textures = dir_ + "/gained_textures";
  StatusOr<EncodeSummary> sum = EncodeCapture(gained.directory, dir_ + "/gained.fvv", s);
  ASSERT_TRUE(sum.ok()) << sum.status().ToString();
  for (uint32_t c : {0u, 1u}) {
    const std::string name = cap->cameras[c].calibration.name;
    StatusOr<Image> plain = ReadImage(TexturePath(dir_ + "/plain_textures", name, 0));
    StatusOr<Image> with = ReadImage(TexturePath(dir_ + "/gained_textures", name, 0));
    StatusOr<Image> plain_mask = ReadImage(TextureMaskPath(dir_ + "/plain_textures", name, 0));
    StatusOr<Image> with_mask = ReadImage(TextureMaskPath(dir_ + "/gained_textures", name, 0));
    ASSERT_TRUE(plain.ok() && with.ok() && plain_mask.ok() && with_mask.ok()) << name;
    size_t compared = 0, equal = 0;
    for (size_t t = 0; t < plain_mask->pixels.size(); ++t) {
      if (plain_mask->pixels[t] != kSeenTexel || with_mask->pixels[t] != kSeenTexel) continue;
      bool same = true;
      for (int k = 0; k < 3; ++k) {
        const double g = c == 1 ? gain[k] : 1.0;
        const long want = std::min(255L, std::lround(plain->pixels[3 * t + k] * g));
        same = same && with->pixels[3 * t + k] == want;
      }
      ++compared, equal += same;
    }
    EXPECT_GT(compared, 1000u) << name;
    EXPECT_EQ(equal, compared) << name;
  }
}

TEST_F(EncodeTest, RefusesBadInputWithErrorsThatNameIt) {
  const std::string out = dir_ + "/bad.fvv";
  auto expect_error = [&](const EncoderSettings& s, const std::string& capture,
                          const std::string& words) {
    StatusOr<EncodeSummary> r = EncodeCapture(capture, out, s);
    ASSERT_FALSE(r.ok()) << "expected an error mentioning '" << words << "'";
    EXPECT_NE(r.status().message().find(words), std::string::npos) << r.status().ToString();
    EXPECT_NE(access(out.c_str(), F_OK), 0) << "a failed encode left " << out;
  };
  expect_error(Settings(), dir_ + "/nowhere", "nowhere");

  EncoderSettings s = Settings();
  s.atlas_size = 8;
  expect_error(s, dir_ + "/cap", "atlas size");
  // The predictive texture codec's requirements.
  s = Settings();
  s.texture_codec = TextureCodec::kPredictive;
  s.masks = false;
  expect_error(s, dir_ + "/cap", "needs masks");
  s.masks = true;
  s.chroma = ChromaFormat::k420;
  expect_error(s, dir_ + "/cap", "4:4:4");

  // Poses of another skeleton.
  {
    std::ofstream(dir_ + "/other.json") << R"({"dof_names": ["hips.rx"], "frames": []})";
    s = Settings();
    s.poses = dir_ + "/other.json";
    expect_error(s, dir_ + "/cap", "dof_names");
  }
  // Poses with a non-finite value, and poses for frames the capture lacks.
  {
    StatusOr<PoseSequence> p = LoadPoseFile(dir_ + "/cap");
    ASSERT_TRUE(p.ok());
    std::string names = "[";
    for (const std::string& n : GenericDofNames())
      names += (names.size() > 1 ? ",\"" : "\"") + n + "\"";
    names += "]";
    std::string dofs = "[";
    for (size_t i = 0; i < GenericDofNames().size(); ++i) dofs += i ? ",0" : "0";
    dofs += "]";
    std::ofstream(dir_ + "/late.json")
        << "{\"dof_names\": " << names << ", \"frames\": [{\"frame\": 40, \"dofs\": " << dofs
        << "}]}";
    s = Settings();
    s.poses = dir_ + "/late.json";
    expect_error(s, dir_ + "/cap", "no frames to encode");
    std::ofstream(dir_ + "/short.json")
        << "{\"dof_names\": " << names << ", \"frames\": [{\"frame\": 0, \"dofs\": [1, 2]}]}";
    s.poses = dir_ + "/short.json";
    expect_error(s, dir_ + "/cap", "DOF values");
  }
  // Textures missing a file, and textures of another atlas size.
  {
    s = Settings();
    s.save_textures = dir_ + "/holes";
    ASSERT_TRUE(EncodeCapture(dir_ + "/cap", dir_ + "/holes.fvv", s).ok());
    StatusOr<Capture> cap = LoadCapture(dir_ + "/cap");
    ASSERT_TRUE(cap.ok());
    const std::string victim =
        TextureMaskPath(dir_ + "/holes", cap->cameras[1].calibration.name, 2);
    ASSERT_EQ(std::remove(victim.c_str()), 0);
    EncoderSettings t = Settings();
    t.poses.clear();
    t.textures = dir_ + "/holes";
    expect_error(t, dir_ + "/cap", victim);
    t.atlas_size = 512;
    expect_error(t, dir_ + "/cap", "atlas_size");
  }
  // An output directory that does not exist.
  {
    StatusOr<EncodeSummary> r =
        EncodeCapture(dir_ + "/cap", dir_ + "/no/such/dir/x.fvv", Settings());
    ASSERT_FALSE(r.ok());
  }
}

TEST_F(EncodeTest, CApiEncodesAndReportsAndRefusesMisuse) {
  // Settings out of range or unknown enum values are refused, with a reason.
  fvv_encoder_settings bad;
  fvv_encoder_default_settings(&bad);
  bad.kernel = 7;
  fvv_encoder* none = nullptr;
  EXPECT_EQ(fvv_encoder_create(&bad, &none), FVV_INVALID_ARGUMENT);
  EXPECT_EQ(none, nullptr);
  EXPECT_NE(std::string(fvv_encoder_settings_error()).find("kernel"), std::string::npos);
  fvv_encoder_default_settings(&bad);
  bad.atlas_size = 5000;
  EXPECT_EQ(fvv_encoder_create(&bad, &none), FVV_INVALID_ARGUMENT);
  EXPECT_EQ(fvv_encoder_create(nullptr, nullptr), FVV_INVALID_ARGUMENT);
  EXPECT_EQ(fvv_encoder_encode_capture(nullptr, "a", "b", nullptr), FVV_INVALID_ARGUMENT);

  fvv_encoder_settings s;
  fvv_encoder_default_settings(&s);
  // The settings `s` refused, the error naming `field`.
  const auto refused = [&](const char* field) -> ::testing::AssertionResult {
    if (fvv_encoder_create(&s, &none) != FVV_INVALID_ARGUMENT) {
      return ::testing::AssertionFailure() << "not refused (" << field << ")";
    }
    const std::string error = fvv_encoder_settings_error();
    if (error.find(field) == std::string::npos) {
      return ::testing::AssertionFailure() << "the error \"" << error << "\" names no " << field;
    }
    return ::testing::AssertionSuccess();
  };
  EXPECT_EQ(s.mask_mode, uint32_t{FVV_MASKS_NONE});  // players take visibility from the geometry
  EXPECT_EQ(s.quantise_model, 1u);                   // the model on a grid: format version 10
  EXPECT_EQ(s.texture_chunks, 1u);                   // the texture in chunks: format version 11
  // The texture tools below write the format versions that introduced them
  // with the model in floats and the texture in 'texr' (otherwise every stream
  // is version 10 or 11).
  s.quantise_model = 0;
  s.texture_chunks = 0;
  // The coding tools below are compared as they were measured: with masks,
  // each tool at the same texture bytes over the same texels.
  s.mask_mode = FVV_MASKS_CODED;
  const std::string poses = dir_ + "/cap";
  s.poses = poses.c_str();
  s.atlas_size = 128;
  s.gop_frames = 3;
  s.rate_mode = FVV_RATE_BPP;
  s.rate_value = 0.5;
  int lines = 0;
  s.progress = [](void* user, const char* line) {
    ++*static_cast<int*>(user);
    EXPECT_NE(std::string(line).find("encode"), std::string::npos);
  };
  s.progress_user = &lines;
  fvv::EncoderPtr enc = fvv::MakeEncoder(&s);
  ASSERT_TRUE(enc);
  EXPECT_EQ(fvv_encoder_add_metadata(enc.get(), nullptr, "x"), FVV_INVALID_ARGUMENT);
  EXPECT_EQ(fvv_encoder_add_metadata(enc.get(), "title", "C API test"), FVV_OK);
  EXPECT_EQ(fvv_encoder_encode_capture(enc.get(), nullptr, "x.fvv", nullptr), FVV_INVALID_ARGUMENT);
  // A missing capture: an error that names it, no output.
  const std::string out = dir_ + "/c_api.fvv";
  EXPECT_EQ(
      fvv_encoder_encode_capture(enc.get(), (dir_ + "/missing").c_str(), out.c_str(), nullptr),
      FVV_IO_ERROR);
  EXPECT_NE(std::string(fvv_encoder_error(enc.get())).find("missing"), std::string::npos);
  EXPECT_NE(access(out.c_str(), F_OK), 0);

  fvv_encode_report report;
  ASSERT_EQ(fvv_encoder_encode_capture(enc.get(), (dir_ + "/cap").c_str(), out.c_str(), &report),
            FVV_OK)
      << fvv_encoder_error(enc.get());
  EXPECT_STREQ(fvv_encoder_error(enc.get()), "");
  EXPECT_EQ(report.frames, 3u);
  EXPECT_EQ(report.cameras, 6u);
  EXPECT_EQ(report.gops, 6u);  // one fragment per camera by default
  EXPECT_GE(lines, 3);
  EXPECT_GT(report.psnr_rgb, 20);
  EXPECT_GT(report.texture_bytes, 0u);
  EXPECT_LE(report.texture_bytes + report.mask_bytes + report.motion_bytes, report.file_bytes);
  // The decoder opens what the encoder wrote, with its metadata.
  fvv::DecoderPtr dec = fvv::MakeDecoder();
  ASSERT_EQ(fvv_decoder_open_file(dec.get(), out.c_str()), FVV_OK) << fvv_decoder_error(dec.get());
  fvv_stream_info info;
  ASSERT_EQ(fvv_decoder_get_info(dec.get(), &info), FVV_OK);
  EXPECT_EQ(info.frame_count, 3u);
  EXPECT_EQ(info.camera_count, 6u);
  // Fractional samples, own-band weights and coder arith3 by default.
  EXPECT_EQ(info.format_version, 7u);

  // FVV_WEIGHTS_AXIS_BANDS: the weights of format versions 1..5 (version 5 with
  // arith3); FVV_CODER_ARITH2: the contexts of format version 4; FVV_CODER_ARITH:
  // those of versions 1..3 (version 3 for the 9/7 precision 5); each at the same
  // bytes and a lower PSNR. An unknown coder or weighting is refused.
  s.progress = nullptr;
  // Encodes the capture with `s` to c_api_<name>.fvv; returns the format
  // version the decoder reads from it (0 when encoding or opening failed).
  const auto encode_version = [&](const char* name, fvv_encode_report* r) -> uint32_t {
    fvv::EncoderPtr e = fvv::MakeEncoder(&s);
    if (!e) return 0;
    const std::string path = dir_ + "/c_api_" + name + ".fvv";
    if (fvv_encoder_encode_capture(e.get(), (dir_ + "/cap").c_str(), path.c_str(), r) != FVV_OK) {
      ADD_FAILURE() << name << ": " << fvv_encoder_error(e.get());
      return 0;
    }
    fvv::DecoderPtr d = fvv::MakeDecoder();
    fvv_stream_info i;
    if (fvv_decoder_open_file(d.get(), path.c_str()) != FVV_OK ||
        fvv_decoder_get_info(d.get(), &i) != FVV_OK)
      return 0;
    return i.format_version;
  };
  // sample_bits = 0: whole samples, what format version 6 decoders read, at
  // the same bytes and a lower PSNR; above 4 is refused.
  // Coder 4: format version 8 (the same settings otherwise).
  s.coder = FVV_CODER_ARITH4;
  fvv_encode_report report_v8;
  EXPECT_EQ(encode_version("v8", &report_v8), 8u);
  EXPECT_GT(report_v8.psnr_rgb, 20.0);
  s.coder = FVV_CODER_ARITH3;
  s.sample_bits = 0;
  fvv_encode_report report_v6;
  EXPECT_EQ(encode_version("v6", &report_v6), 6u);
  EXPECT_LT(report_v6.psnr_rgb, report.psnr_rgb);
  s.sample_bits = 5;
  EXPECT_TRUE(refused("sample_bits"));
  s.sample_bits = 3;
  s.prune = 2;  // a flag: 0 or 1
  EXPECT_TRUE(refused("prune"));
  s.prune = 1;
  // The model on a grid: format version 10, the same textures' bytes, a
  // smaller stream; a value other than 0 or 1 is refused.
  s.sample_bits = 3;
  s.quantise_model = 1;
  fvv_encode_report report_v10;
  EXPECT_EQ(encode_version("v10", &report_v10), 10u);
  EXPECT_LT(report_v10.file_bytes, report.file_bytes);
  EXPECT_NEAR(double(report_v10.texture_bytes), double(report.texture_bytes),
              0.02 * double(report.texture_bytes));
  EXPECT_NEAR(report_v10.psnr_rgb, report.psnr_rgb, 0.2);
  // The texture in chunks: format version 11, the same samples and texture
  // bytes; 7 bytes a chunk instead of 'texr''s truncation points, within a
  // few percent of the stream.
  s.texture_chunks = 1;
  fvv_encode_report report_v11;
  EXPECT_EQ(encode_version("v11", &report_v11), 11u);
  EXPECT_EQ(report_v11.texture_bytes, report_v10.texture_bytes);
  EXPECT_EQ(report_v11.psnr_rgb, report_v10.psnr_rgb);
  EXPECT_NEAR(double(report_v11.file_bytes), double(report_v10.file_bytes),
              0.03 * double(report_v10.file_bytes));
  s.texture_chunks = 2;
  EXPECT_TRUE(refused("texture_chunks"));
  s.texture_chunks = 0;
  s.quantise_model = 2;
  EXPECT_TRUE(refused("quantise_model"));
  s.quantise_model = 0;
  s.surface = 2;
  EXPECT_TRUE(refused("surface"));
  // The surface rides in the texture's chunks: not without them.
  s.surface = 1;
  EXPECT_TRUE(refused("chunks"));
  s.surface = 0;
  // Something else in the silhouettes kept out, and the nearest frames' fill:
  // on by default.
  EXPECT_EQ(s.occluders, 1u);
  EXPECT_EQ(s.temporal_fill_frames, 15u);
  s.occluders = 2;
  EXPECT_TRUE(refused("occluders"));
  s.occluders = 1;
  s.temporal_fill_frames = 100001;
  EXPECT_TRUE(refused("temporal_fill_frames"));
  s.temporal_fill_frames = 15;
  // The blend-share rule: a share outside 0..1 is refused.
  EXPECT_DOUBLE_EQ(s.least_blend_share, 0.25);
  for (double share : {-0.1, 1.5, std::nan("")}) {
    s.least_blend_share = share;
    EXPECT_TRUE(refused("least_blend_share"));
  }
  s.least_blend_share = 0.25;
  s.sample_bits = 0;
  s.weights = FVV_WEIGHTS_AXIS_BANDS;
  fvv_encode_report report_v5;
  EXPECT_EQ(encode_version("v5", &report_v5), 5u);
  EXPECT_LT(report_v5.psnr_rgb, report_v6.psnr_rgb);
  s.weights = 2;
  EXPECT_TRUE(refused("weights"));
  s.weights = FVV_WEIGHTS_AXIS_BANDS;
  s.coder = FVV_CODER_ARITH2;
  fvv_encode_report report_v4;
  EXPECT_EQ(encode_version("v4", &report_v4), 4u);
  EXPECT_LT(report_v4.psnr_rgb, report_v5.psnr_rgb);
  s.coder = FVV_CODER_ARITH;
  fvv_encode_report report_v3;
  EXPECT_EQ(encode_version("v3", &report_v3), 3u);
  EXPECT_LT(report_v3.psnr_rgb, report_v4.psnr_rgb);
  s.coder = 5;
  EXPECT_TRUE(refused("coder"));
  s.coder = FVV_CODER_ARITH;

  // precision_97 = 2: the 9/7 as format versions 1 and 2 have it (format
  // version 2 for the masks), at a lower PSNR for the same bytes.
  s.precision_97 = 2;
  fvv_encode_report report_v2;
  EXPECT_EQ(encode_version("v2", &report_v2), 2u);
  EXPECT_LT(report_v2.psnr_rgb, report.psnr_rgb);

  // FVV_MASKS_CODED_V1 as well: mask mode 1 keeps the stream at format version
  // 1, with larger masks; an unknown mask mode is refused.
  s.mask_mode = FVV_MASKS_CODED_V1;
  fvv_encode_report report_v1;
  EXPECT_EQ(encode_version("v1", &report_v1), 1u);
  EXPECT_EQ(report_v1.texture_bytes, report_v2.texture_bytes);
  EXPECT_GT(report_v1.mask_bytes, report_v2.mask_bytes);
  s.mask_mode = 3;
  EXPECT_TRUE(refused("mask_mode"));
  s.mask_mode = FVV_MASKS_CODED;
  for (uint32_t precision : {1u, 7u}) {
    s.precision_97 = precision;
    EXPECT_TRUE(refused("precision_97"));
  }
}

}  // namespace
}  // namespace fvv
