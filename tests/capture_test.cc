// Capture directories and calibration: projection round trips,
// calibration sanity checks, capture.json errors that name what is wrong,
// frame sources (PNG, EXR and JPEG image sequences, ffmpeg-decoded video).
#include "encoder/capture/capture.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <turbojpeg.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>

#include "encoder/capture/calibration.h"
#include "encoder/capture/calibration_import.h"
#include "encoder/capture/up_axis.h"
#include "encoder/capture/video_reader.h"

namespace fvv {
namespace {

Camera TestCamera(double k1 = -0.2, double k2 = 0.05) {
  Camera c = LookAtCamera("a", 640, 480, 700, Eigen::Vector3d(2, 1.5, 3), Eigen::Vector3d(0, 1, 0),
                          Eigen::Vector3d(0, 1, 0));
  c.cx = 322.5;
  c.cy = 236.0;
  c.fy = 705;
  c.distortion = {k1, k2, 0.001, -0.0015, 0.01};
  return c;
}

TEST(Calibration, ProjectUnprojectRoundTrip) {
  const Camera c = TestCamera();
  ASSERT_TRUE(ValidateCalibration(c, "test").ok()) << ValidateCalibration(c, "test").ToString();
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.8, 0.8);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d world(u(rng), 1 + u(rng), u(rng));
    Eigen::Vector2d px;
    double depth = 0;
    ASSERT_TRUE(ProjectPoint(c, world, &px, &depth));
    const Eigen::Vector3d back = UnprojectPixel(c, px, depth);
    EXPECT_LT((back - world).norm(), 1e-8);
  }
  // The camera centre projects nowhere; the look-at target lands near the image centre.
  Eigen::Vector2d px;
  EXPECT_FALSE(ProjectPoint(c, CameraCentre(c), &px));
  Camera plain = TestCamera(0, 0);
  plain.distortion = {};
  ASSERT_TRUE(ProjectPoint(plain, Eigen::Vector3d(0, 1, 0), &px));
  EXPECT_NEAR(px.x(), plain.cx, 1e-9);
  EXPECT_NEAR(px.y(), plain.cy, 1e-9);
}

TEST(Calibration, RejectsBrokenCalibrations) {
  Camera c = TestCamera();
  c.rotation[0] = -c.rotation[0], c.rotation[1] = -c.rotation[1], c.rotation[2] = -c.rotation[2];
  EXPECT_NE(ValidateCalibration(c, "cam").message().find("reflection"), std::string::npos);
  c = TestCamera();
  c.rotation[4] *= 1.01;
  EXPECT_NE(ValidateCalibration(c, "cam").message().find("orthonormal"), std::string::npos);
  c = TestCamera();
  c.fx = -5;
  EXPECT_NE(ValidateCalibration(c, "cam").message().find("focal"), std::string::npos);
  c = TestCamera(-1.5, 0.0);  // folds over inside the image
  EXPECT_NE(ValidateCalibration(c, "cam").message().find("monotonic"), std::string::npos);
}

nlohmann::json ValidCaptureJson() {
  const Camera c = TestCamera();
  nlohmann::json cam = {
      {"name", "left"},
      {"width", 640},
      {"height", 480},
      {"K", {{c.fx, 0, c.cx}, {0, c.fy, c.cy}, {0, 0, 1}}},
      {"distortion", c.distortion},
      {"R", c.rotation},
      {"t", c.translation},
      {"frames", {{"images", "left/%04d.png"}, {"first", 1}}},
  };
  nlohmann::json cam2 = cam;
  cam2["name"] = "right";
  cam2["frames"] = {{"images", "right/f%d.png"}};
  return {{"format", "fvv-capture"}, {"version", 1},   {"frame_rate", 25},
          {"frame_count", 3},        {"up_axis", "y"}, {"cameras", {cam, cam2}}};
}

TEST(Capture, ParsesAndRoundTrips) {
  StatusOr<Capture> c = ParseCapture(ValidCaptureJson().dump(), "/data/take1");
  ASSERT_TRUE(c.ok()) << c.status().ToString();
  ASSERT_EQ(c->cameras.size(), 2u);
  EXPECT_EQ(FramePath(*c, c->cameras[0].frames, 2), "/data/take1/left/0003.png");
  EXPECT_EQ(FramePath(*c, c->cameras[1].frames, 12), "/data/take1/right/f12.png");
  StatusOr<Capture> again = ParseCapture(CaptureToJson(*c), "/data/take1");
  ASSERT_TRUE(again.ok()) << again.status().ToString();
  EXPECT_EQ(again->cameras[1].calibration.rotation, c->cameras[1].calibration.rotation);
  EXPECT_EQ(again->cameras[0].frames.first, 1);
  // A camera's colour gain: absent is 1, 1, 1 (and not written); set, it
  // comes back as written.
  EXPECT_EQ(c->cameras[0].colour_gain, (std::array<double, 3>{1, 1, 1}));
  EXPECT_EQ(CaptureToJson(*c).find("colour_gain"), std::string::npos);
  c->cameras[1].colour_gain = {0.9, 1.05, 1.25};
  again = ParseCapture(CaptureToJson(*c), "/data/take1");
  ASSERT_TRUE(again.ok()) << again.status().ToString();
  EXPECT_EQ(again->cameras[1].colour_gain, c->cameras[1].colour_gain);
  EXPECT_EQ(again->cameras[0].colour_gain, (std::array<double, 3>{1, 1, 1}));
}

// A z-up capture (as many studios calibrate) is turned into fvv's y-up world:
// every point projects where its y-up twin does, and the cameras stand as high.
TEST(Capture, ZUpCapturesAreTurnedIntoTheYUpWorld) {
  // The camera of TestCamera, calibrated in a z-up world: eye (2, 1.5, 3) and
  // target (0, 1, 0) in y-up are (2, -3, 1.5) and (0, 0, 1) in z-up.
  Camera z_cam = LookAtCamera("a", 640, 480, 700, Eigen::Vector3d(2, -3, 1.5),
                              Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(0, 0, 1));
  z_cam.distortion = {-0.2, 0.05, 0.001, -0.0015, 0.01};
  nlohmann::json j = ValidCaptureJson();
  j["up_axis"] = "z";
  for (auto& cam : j["cameras"]) {
    cam["R"] = z_cam.rotation;
    cam["t"] = z_cam.translation;
    cam["distortion"] = z_cam.distortion;
    cam["K"] = {{z_cam.fx, 0, z_cam.cx}, {0, z_cam.fy, z_cam.cy}, {0, 0, 1}};
  }
  StatusOr<Capture> c = ParseCapture(j.dump(), "/data/take1");
  ASSERT_TRUE(c.ok()) << c.status().ToString();
  EXPECT_EQ(c->up_axis, 'y');
  EXPECT_EQ(c->declared_up_axis, 'z');
  const Camera& y_cam = c->cameras[0].calibration;
  EXPECT_NEAR(CameraCentre(y_cam).y(), 1.5, 1e-9);
  EXPECT_NEAR(CameraCentre(y_cam).z(), 3.0, 1e-9);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-0.8, 0.8);
  for (int i = 0; i < 50; ++i) {
    const Eigen::Vector3d z_point(u(rng), u(rng), 1 + u(rng));
    const Eigen::Vector3d y_point(z_point.x(), z_point.z(), -z_point.y());
    Eigen::Vector2d pz, py;
    ASSERT_TRUE(ProjectPoint(z_cam, z_point, &pz));
    ASSERT_TRUE(ProjectPoint(y_cam, y_point, &py));
    EXPECT_LT((pz - py).norm(), 1e-9) << "point " << i;
  }
  // Saved again, the capture is y-up and reads back the same cameras.
  StatusOr<Capture> again = ParseCapture(CaptureToJson(*c), "/data/take1");
  ASSERT_TRUE(again.ok()) << again.status().ToString();
  EXPECT_EQ(again->declared_up_axis, 'y');
  EXPECT_EQ(again->cameras[0].calibration.rotation, y_cam.rotation);
}

// Each malformed capture.json is refused with a message naming the problem.
TEST(Capture, MalformedCapturesNameTheProblem) {
  struct Case {
    const char* what;
    std::function<void(nlohmann::json*)> edit;
    const char* expect;
  };
  const std::vector<Case> cases = {
      {"not json", nullptr, "not valid JSON"},
      {"wrong format", [](nlohmann::json* j) { (*j)["format"] = "x"; }, "\"format\""},
      {"newer version", [](nlohmann::json* j) { (*j)["version"] = 2; }, "version 2"},
      {"no cameras", [](nlohmann::json* j) { (*j)["cameras"] = nlohmann::json::array(); },
       "cameras"},
      {"zero frames", [](nlohmann::json* j) { (*j)["frame_count"] = 0; }, "frame_count"},
      {"bad rate", [](nlohmann::json* j) { (*j)["frame_rate"] = -1; }, "frame_rate"},
      {"bad up axis", [](nlohmann::json* j) { (*j)["up_axis"] = "x"; }, "up_axis"},
      {"missing K", [](nlohmann::json* j) { (*j)["cameras"][1].erase("K"); },
       "cameras[1] (\"right\"): missing \"K\""},
      {"skewed K", [](nlohmann::json* j) { (*j)["cameras"][0]["K"][0][1] = 3; }, "no skew"},
      {"K not 3x3",
       [](nlohmann::json* j) {
         (*j)["cameras"][0]["K"] = {1, 2, 3};
       },
       "3x3"},
      {"R reflection",
       [](nlohmann::json* j) {
         for (int i = 0; i < 3; ++i)
           (*j)["cameras"][1]["R"][i] = -(*j)["cameras"][1]["R"][i].get<double>();
       },
       "cameras[1] (\"right\"): R is a reflection"},
      {"t not numbers",
       [](nlohmann::json* j) {
         (*j)["cameras"][0]["t"] = {1, "a", 3};
       },
       "t: expected a number"},
      {"bad size", [](nlohmann::json* j) { (*j)["cameras"][0]["width"] = 0; }, "width"},
      {"duplicate names", [](nlohmann::json* j) { (*j)["cameras"][1]["name"] = "left"; },
       "duplicate camera name"},
      {"pattern without number",
       [](nlohmann::json* j) { (*j)["cameras"][0]["frames"]["images"] = "left/a.png"; },
       "exactly one frame number"},
      {"pattern with %s",
       [](nlohmann::json* j) { (*j)["cameras"][0]["frames"]["images"] = "left/%s.png"; },
       "%d or %0Nd"},
      {"images and video",
       [](nlohmann::json* j) { (*j)["cameras"][0]["frames"]["video"] = "a.mp4"; },
       "exactly one of"},
      {"colour gain of two numbers",
       [](nlohmann::json* j) {
         (*j)["cameras"][1]["colour_gain"] = {1, 1};
       },
       "cameras[1] (\"right\").colour_gain: expected 3 numbers"},
      {"colour gain of zero",
       [](nlohmann::json* j) {
         (*j)["cameras"][0]["colour_gain"] = {1, 0, 1};
       },
       "gains must lie in [0.25, 4]"},
      {"colour gain not a number",
       [](nlohmann::json* j) {
         (*j)["cameras"][0]["colour_gain"] = {1, "x", 1};
       },
       "colour_gain: expected a number"},
      {"too many distortion terms",
       [](nlohmann::json* j) { (*j)["cameras"][0]["distortion"] = {0, 0, 0, 0, 0, 0}; }, "up to 5"},
  };
  for (const Case& c : cases) {
    std::string text = "{not json";
    if (c.edit) {
      nlohmann::json j = ValidCaptureJson();
      c.edit(&j);
      text = j.dump();
    }
    StatusOr<Capture> r = ParseCapture(text, ".");
    ASSERT_FALSE(r.ok()) << c.what;
    EXPECT_NE(r.status().message().find(c.expect), std::string::npos)
        << c.what << ": " << r.status().message();
  }
}

class CaptureFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = ::testing::TempDir() + "/capture_files_" +
           ::testing::UnitTest::GetInstance()->current_test_info()->name() + "_" +
           std::to_string(getpid());
    std::system(
        ("rm -rf '" + dir_ + "' && mkdir -p '" + dir_ + "/left' '" + dir_ + "/right'").c_str());
  }
  void TearDown() override { std::system(("rm -rf '" + dir_ + "'").c_str()); }
  Image Frame(uint32_t w, uint32_t h, int seed) {
    Image img;
    img.width = w, img.height = h;
    img.pixels.resize(size_t{w} * h * 3);
    for (size_t i = 0; i < img.pixels.size(); ++i)
      img.pixels[i] = uint8_t((i * 7 + seed * 31) % 251);
    return img;
  }
  std::string dir_;
};

TEST_F(CaptureFiles, ReadsFramesAndNamesMissingOrWrongOnes) {
  nlohmann::json j = ValidCaptureJson();
  j["cameras"][0]["width"] = 64, j["cameras"][0]["height"] = 48;
  j["cameras"][1]["width"] = 64, j["cameras"][1]["height"] = 48;
  for (auto& cam : j["cameras"]) {
    cam["K"] = {{60, 0, 32}, {0, 60, 24}, {0, 0, 1}};
    cam["distortion"] = {0, 0, 0, 0, 0};
  }
  std::ofstream(dir_ + "/capture.json") << j.dump();
  for (int f = 0; f < 3; ++f) {
    char name[64];
    std::snprintf(name, sizeof(name), "/left/%04d.png", f + 1);
    ASSERT_TRUE(WritePng(dir_ + name, Frame(64, 48, f)).ok());
  }
  ASSERT_TRUE(WritePng(dir_ + "/right/f0.png", Frame(64, 48, 9)).ok());
  ASSERT_TRUE(WritePng(dir_ + "/right/f1.png", Frame(32, 48, 9)).ok());  // wrong size
  StatusOr<Capture> c = LoadCapture(dir_);
  ASSERT_TRUE(c.ok()) << c.status().ToString();
  CaptureReader reader(*c);
  StatusOr<Image> f2 = reader.ReadFrame(0, 2);
  ASSERT_TRUE(f2.ok()) << f2.status().ToString();
  EXPECT_EQ(f2->pixels, Frame(64, 48, 2).pixels);
  StatusOr<Image> wrong = reader.ReadFrame(1, 1);
  ASSERT_FALSE(wrong.ok());
  EXPECT_NE(wrong.status().message().find("camera \"right\", frame 1: image is 32x48"),
            std::string::npos)
      << wrong.status().message();
  StatusOr<Image> missing = reader.ReadFrame(1, 2);
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.status().message().find("camera \"right\", frame 2"), std::string::npos);
  Status check = reader.CheckFiles();
  EXPECT_NE(check.message().find("missing file"), std::string::npos) << check.message();
  EXPECT_FALSE(reader.ReadFrame(0, 3).ok());  // beyond frame_count
  EXPECT_FALSE(LoadCapture(dir_ + "/nowhere").ok());
}

TEST_F(CaptureFiles, ReadsExrSequencesAndSilhouettes) {
  nlohmann::json j = ValidCaptureJson();
  j["cameras"].erase(1);
  j["cameras"][0]["width"] = 32, j["cameras"][0]["height"] = 24;
  j["cameras"][0]["K"] = {{30, 0, 16}, {0, 30, 12}, {0, 0, 1}};
  j["cameras"][0]["distortion"] = {0, 0, 0, 0, 0};
  j["cameras"][0]["frames"] = {{"images", "left/%03d.exr"}};
  j["cameras"][0]["silhouettes"] = {{"images", "left/s%03d.png"}};
  std::ofstream(dir_ + "/capture.json") << j.dump();
  Image sil;
  sil.width = 32, sil.height = 24, sil.channels = 1;
  sil.pixels.assign(32 * 24, 0);
  sil.pixels[5] = 1;  // any non-zero value is the actor
  for (int f = 0; f < 3; ++f) {
    char name[64];
    std::snprintf(name, sizeof(name), "/left/%03d.exr", f);
    ASSERT_TRUE(WriteExr(dir_ + name, Frame(32, 24, f)).ok());
    std::snprintf(name, sizeof(name), "/left/s%03d.png", f);
    ASSERT_TRUE(WritePng(dir_ + name, sil).ok());
  }
  StatusOr<Capture> c = LoadCapture(dir_ + "/capture.json");
  ASSERT_TRUE(c.ok()) << c.status().ToString();
  CaptureReader reader(*c);
  EXPECT_TRUE(reader.HasSilhouettes());
  EXPECT_FALSE(reader.HasBackgrounds());
  StatusOr<Image> f1 = reader.ReadFrame(0, 1);
  ASSERT_TRUE(f1.ok()) << f1.status().ToString();
  EXPECT_EQ(f1->pixels, Frame(32, 24, 1).pixels);  // 8-bit values survive EXR's half floats
  StatusOr<Image> s1 = reader.ReadSilhouette(0, 1);
  ASSERT_TRUE(s1.ok()) << s1.status().ToString();
  EXPECT_EQ(s1->pixels[5], 255);
  EXPECT_EQ(s1->pixels[6], 0);
  EXPECT_FALSE(reader.ReadBackground(0).ok());
}

// A JPEG of `img` through libjpeg-turbo's encoder (the test's own maker: fvv
// only reads JPEG).
std::vector<uint8_t> EncodeJpeg(const Image& img, int quality) {
  tjhandle tj = tjInitCompress();
  unsigned char* out = nullptr;
  unsigned long size = 0;
  const int rc = tjCompress2(tj, img.pixels.data(), int(img.width), 0, int(img.height),
                             img.channels == 1 ? TJPF_GRAY : TJPF_RGB, &out, &size,
                             img.channels == 1 ? TJSAMP_GRAY : TJSAMP_420, quality, 0);
  std::vector<uint8_t> bytes;
  if (rc == 0) bytes.assign(out, out + size);
  tjFree(out);
  tjDestroy(tj);
  return bytes;
}

void WriteBytes(const std::string& path, const std::vector<uint8_t>& bytes) {
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

double Psnr(const Image& a, const Image& b) {
  double se = 0;
  for (size_t i = 0; i < a.pixels.size(); ++i) {
    const double d = double(a.pixels[i]) - b.pixels[i];
    se += d * d;
  }
  return 10 * std::log10(255.0 * 255.0 * double(a.pixels.size()) / std::max(se, 1e-9));
}

TEST_F(CaptureFiles, ReadsJpegSequencesAndRefusesDamagedOnes) {
  nlohmann::json j = ValidCaptureJson();
  j["cameras"].erase(1);
  j["cameras"][0]["width"] = 96, j["cameras"][0]["height"] = 64;
  j["cameras"][0]["K"] = {{90, 0, 48}, {0, 90, 32}, {0, 0, 1}};
  j["cameras"][0]["distortion"] = {0, 0, 0, 0, 0};
  j["cameras"][0]["frames"] = {{"images", "left/%03d.jpg"}};
  std::ofstream(dir_ + "/capture.json") << j.dump();
  // Smooth frames, as a camera sees: JPEG keeps them within a few levels.
  auto smooth = [](int seed, int channels) {
    Image img;
    img.width = 96, img.height = 64, img.channels = channels;
    img.pixels.resize(size_t{96} * 64 * channels);
    for (uint32_t y = 0; y < 64; ++y)
      for (uint32_t x = 0; x < 96; ++x)
        for (int c = 0; c < channels; ++c)
          img.pixels[(y * 96 + x) * channels + c] =
              uint8_t(128 + 90 * std::sin(0.07 * x + 0.05 * y + seed + 2.0 * c));
    return img;
  };
  std::vector<std::vector<uint8_t>> files;
  for (int f = 0; f < 3; ++f) {
    files.push_back(EncodeJpeg(smooth(f, 3), 95));
    ASSERT_FALSE(files.back().empty());
    char name[64];
    std::snprintf(name, sizeof(name), "/left/%03d.jpg", f);
    WriteBytes(dir_ + name, files.back());
  }
  StatusOr<Capture> c = LoadCapture(dir_);
  ASSERT_TRUE(c.ok()) << c.status().ToString();
  CaptureReader reader(*c);
  EXPECT_TRUE(reader.CheckFiles().ok());
  for (uint32_t f = 0; f < 3; ++f) {
    StatusOr<Image> got = reader.ReadFrame(0, f);
    ASSERT_TRUE(got.ok()) << got.status().ToString();
    ASSERT_EQ(got->channels, 3);
    ASSERT_EQ(got->pixels.size(), smooth(int(f), 3).pixels.size());
    EXPECT_GT(Psnr(*got, smooth(int(f), 3)), 35.0) << "frame " << f;
    // Not another frame's picture.
    EXPECT_LT(Psnr(*got, smooth(int(f + 1), 3)), 25.0) << "frame " << f;
  }
  // Grey JPEGs stay grey; the extension's case does not matter.
  WriteBytes(dir_ + "/grey.JPEG", EncodeJpeg(smooth(4, 1), 95));
  StatusOr<Image> grey = ReadImage(dir_ + "/grey.JPEG");
  ASSERT_TRUE(grey.ok()) << grey.status().ToString();
  EXPECT_EQ(grey->channels, 1);
  EXPECT_GT(Psnr(*grey, smooth(4, 1)), 35.0);
  // Damaged files: each refused with its own reason, never a partial picture.
  struct Case {
    const char* what;
    std::vector<uint8_t> bytes;
    const char* expect;
  };
  std::vector<uint8_t> truncated(files[1].begin(), files[1].begin() + files[1].size() / 2);
  std::vector<uint8_t> huge = files[1];
  // The frame header (SOF0: FF C0, length, precision, height, width): claim
  // 30000 x 30000 pixels (within JPEG's limit, over fvv's 2^28), which must
  // be refused before anything is allocated.
  for (size_t i = 0; i + 8 < huge.size(); ++i) {
    if (huge[i] == 0xFF && huge[i + 1] == 0xC0) {
      huge[i + 5] = huge[i + 7] = 0x75;
      huge[i + 6] = huge[i + 8] = 0x30;
      break;
    }
  }
  const Case cases[] = {
      {"truncated", truncated, "JPEG decoding failed"},
      {"not a JPEG", std::vector<uint8_t>(200, 0x42), "not a readable JPEG"},
      {"empty", {}, "empty file"},
      {"30000 x 30000", huge, "too large"},
  };
  for (const Case& k : cases) {
    WriteBytes(dir_ + "/left/001.jpg", k.bytes);
    StatusOr<Image> bad = reader.ReadFrame(0, 1);
    ASSERT_FALSE(bad.ok()) << k.what;
    EXPECT_NE(bad.status().message().find(k.expect), std::string::npos)
        << k.what << ": " << bad.status().message();
    EXPECT_NE(bad.status().message().find("001.jpg"), std::string::npos) << k.what;
  }
}

TEST_F(CaptureFiles, VideoFramesDecodeThroughFfmpeg) {
  if (!HaveFfmpeg()) GTEST_SKIP() << "ffmpeg not installed (tools/setup.sh installs it)";
  for (int f = 0; f < 4; ++f) {
    char name[64];
    std::snprintf(name, sizeof(name), "/left/%04d.png", f);
    ASSERT_TRUE(WritePng(dir_ + name, Frame(64, 48, f)).ok());
  }
  // A lossless RGB video, so decoded frames must equal the source exactly.
  const std::string cmd = "ffmpeg -v error -y -framerate 25 -i '" + dir_ +
                          "/left/%04d.png' -c:v png '" + dir_ + "/left.mkv'";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  nlohmann::json j = ValidCaptureJson();
  j["frame_count"] = 4;
  j["cameras"].erase(1);
  j["cameras"][0]["width"] = 64, j["cameras"][0]["height"] = 48;
  j["cameras"][0]["K"] = {{60, 0, 32}, {0, 60, 24}, {0, 0, 1}};
  j["cameras"][0]["distortion"] = {0, 0, 0, 0, 0};
  j["cameras"][0]["frames"] = {{"video", "left.mkv"}};
  std::ofstream(dir_ + "/capture.json") << j.dump();
  StatusOr<Capture> c = LoadCapture(dir_);
  ASSERT_TRUE(c.ok()) << c.status().ToString();
  CaptureReader reader(*c);
  for (int f : {0, 1, 3, 2}) {  // forwards, a skip, and back again (restarts the decoder)
    StatusOr<Image> img = reader.ReadFrame(0, f);
    ASSERT_TRUE(img.ok()) << img.status().ToString();
    EXPECT_EQ(img->pixels, Frame(64, 48, f).pixels) << "frame " << f;
  }
  // A Matroska file says no frame count: the check passes and the reader
  // fails at the frame. A QuickTime file says 4: frame 4 is refused before
  // any decoding, and so is frame 3 when the camera skips its first frame.
  EXPECT_TRUE(CheckFramesPresent(*c, {0, 7}).ok());
  const std::string mov = "ffmpeg -v error -y -framerate 25 -i '" + dir_ +
                          "/left/%04d.png' -c:v png '" + dir_ + "/left.mov'";
  ASSERT_EQ(std::system(mov.c_str()), 0);
  c->cameras[0].frames.path = "left.mov";
  EXPECT_TRUE(CheckFramesPresent(*c, {0, 1, 2, 3}).ok());
  Status past = CheckFramesPresent(*c, {2, 4});
  ASSERT_FALSE(past.ok());
  EXPECT_NE(past.message().find("left.mov: no frame 4 (its container says it holds 4 frames"),
            std::string::npos)
      << past.message();
  c->cameras[0].frames.first = 1;
  Status skipped = CheckFramesPresent(*c, {3});
  ASSERT_FALSE(skipped.ok());
  EXPECT_NE(skipped.message().find("no frame 4"), std::string::npos) << skipped.message();
  // An image sequence: the files of the frames asked for, and only those.
  c->cameras[0].frames = FrameSource{};
  c->cameras[0].frames.path = "left/%04d.png";
  EXPECT_TRUE(CheckFramesPresent(*c, {0, 2, 3}).ok());
  ASSERT_EQ(std::remove((dir_ + "/left/0001.png").c_str()), 0);
  EXPECT_TRUE(CheckFramesPresent(*c, {0, 2, 3}).ok());
  Status gone = CheckFramesPresent(*c, {0, 1, 2});
  ASSERT_FALSE(gone.ok());
  EXPECT_NE(gone.message().find("frame 1: missing file"), std::string::npos) << gone.message();
  // A video whose size differs from the calibration is named as such.
  StatusOr<std::unique_ptr<VideoReader>> wrong = VideoReader::Open(dir_ + "/left.mkv", 32, 48);
  ASSERT_FALSE(wrong.ok());
  EXPECT_NE(wrong.status().message().find("64x48"), std::string::npos) << wrong.status().message();
}

std::string List(const double* v, int n) {
  std::string s;
  char buf[64];
  for (int i = 0; i < n; ++i) {
    std::snprintf(buf, sizeof(buf), "%s%.17g", i ? ", " : "", v[i]);
    s += buf;
  }
  return s;
}

// OpenCV FileStorage YAML (rvec, tvec in millimetres) and TOML (two cameras,
// R and t in metres) import to the same cameras: identical projections.
TEST_F(CaptureFiles, ImportsOpenCvYamlAndToml) {
  const Camera truth = TestCamera();
  const Eigen::AngleAxisd aa(CameraRotation(truth));
  const Eigen::Vector3d rvec = aa.angle() * aa.axis();
  const double tvec_mm[3] = {truth.translation[0] * 1000, truth.translation[1] * 1000,
                             truth.translation[2] * 1000};
  const double k[9] = {truth.fx, 0, truth.cx, 0, truth.fy, truth.cy, 0, 0, 1};
  std::ofstream(dir_ + "/left.yml")
      << "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\n"
      << "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [ "
      << List(k, 9) << " ]\n"
      << "distortion_coefficients: !!opencv-matrix\n   rows: 1\n   cols: 5\n   dt: d\n   data: [ "
      << List(truth.distortion.data(), 5) << " ]\n"
      << "rvec: !!opencv-matrix\n   rows: 3\n   cols: 1\n   dt: d\n   data: [ "
      << List(rvec.data(), 3) << " ]\n"
      << "tvec: !!opencv-matrix\n   rows: 3\n   cols: 1\n   dt: d\n   data: [ " << List(tvec_mm, 3)
      << " ]\n";
  std::ofstream toml(dir_ + "/rig.toml");
  for (const char* name : {"cam_a", "cam_b"}) {
    toml << "[" << name << "]\nwidth = 640\nheight = 480\nK = [" << List(k, 9) << "]\n"
         << "dist = [" << List(truth.distortion.data(), 5) << "]\nR = ["
         << List(truth.rotation.data(), 9) << "]\nt = [" << List(truth.translation.data(), 3)
         << "]\n\n";
  }
  toml.close();
  StatusOr<std::vector<Camera>> yaml = ImportCalibrationFile(dir_ + "/left.yml", 0.001);
  ASSERT_TRUE(yaml.ok()) << yaml.status().ToString();
  StatusOr<std::vector<Camera>> rig = ImportCalibrationFile(dir_ + "/rig.toml", 1.0);
  ASSERT_TRUE(rig.ok()) << rig.status().ToString();
  ASSERT_EQ(yaml->size(), 1u);
  ASSERT_EQ(rig->size(), 2u);
  EXPECT_EQ((*yaml)[0].name, "left");
  EXPECT_EQ((*rig)[1].name, "cam_b");
  for (const Camera& c : {(*yaml)[0], (*rig)[0], (*rig)[1]}) {
    for (const Eigen::Vector3d& p : {Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(0.3, 1.6, -0.2)}) {
      Eigen::Vector2d a, b;
      ASSERT_TRUE(ProjectPoint(truth, p, &a));
      ASSERT_TRUE(ProjectPoint(c, p, &b));
      EXPECT_LT((a - b).norm(), 1e-6) << c.name;
    }
  }
  // Errors name the file and what is missing or wrong.
  std::ofstream(dir_ + "/bad.yml") << "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\n"
                                   << "rvec: [0, 0, 0]\ntvec: [0, 0, 1]\n";
  StatusOr<std::vector<Camera>> bad = ImportCalibrationFile(dir_ + "/bad.yml", 1.0);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.status().message().find("bad.yml"), std::string::npos);
  EXPECT_NE(bad.status().message().find("no camera"), std::string::npos) << bad.status().message();
  std::ofstream(dir_ + "/mirror.toml")
      << "[x]\nwidth = 64\nheight = 48\nK = [60, 0, 32, 0, 60, 24, 0, 0, 1]\n"
      << "R = [-1, 0, 0, 0, 1, 0, 0, 0, 1]\nt = [0, 0, 1]\n";
  bad = ImportCalibrationFile(dir_ + "/mirror.toml", 1.0);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.status().message().find("reflection"), std::string::npos) << bad.status().message();
  std::ofstream(dir_ + "/broken.toml") << "[x\nwidth = ";
  EXPECT_FALSE(ImportCalibrationFile(dir_ + "/broken.toml", 1.0).ok());
  // An image size no camera has is refused before it becomes an integer, in
  // either spelling: beyond every integer type, negative, fractional.
  struct BadSize {
    const char* lines;
    const char* field;
    const char* shown;
  };
  const BadSize sizes[] = {{"width = 6.5e53\nheight = 48\n", "image width", "6.5e+53"},
                           {"width = 64\nheight = -48\n", "image height", "-48"},
                           {"size = [64.5, 48]\n", "image width", "64.5"},
                           {"size = [64, 1e300]\n", "image height", "1e+300"}};
  for (const BadSize& b : sizes) {
    std::ofstream(dir_ + "/size.toml") << "[x]\n"
                                       << b.lines << "K = [60, 0, 32, 0, 60, 24, 0, 0, 1]\n"
                                       << "R = [1, 0, 0, 0, 1, 0, 0, 0, 1]\nt = [0, 0, 1]\n";
    bad = ImportCalibrationFile(dir_ + "/size.toml", 1.0);
    ASSERT_FALSE(bad.ok()) << b.lines;
    const std::string& m = bad.status().message();
    EXPECT_NE(m.find(std::string(b.field) + " " + b.shown + " is not a whole number of pixels"),
              std::string::npos)
        << m;
  }
}

}  // namespace

// The camera every import test describes, and the check that an imported camera
// is it: known points project to the same pixels (to 1e-6 px), and a point on
// the optical axis lands on the principal point.
void ExpectSameCamera(const Camera& truth, const Camera& c) {
  EXPECT_EQ(c.width, truth.width) << c.name;
  EXPECT_EQ(c.height, truth.height) << c.name;
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(0.3, 1.6, -0.2),
                                   Eigen::Vector3d(-0.5, 0.2, 0.4)}) {
    Eigen::Vector2d a, b;
    ASSERT_TRUE(ProjectPoint(truth, p, &a));
    ASSERT_TRUE(ProjectPoint(c, p, &b)) << c.name;
    EXPECT_LT((a - b).norm(), 1e-6) << c.name << " at " << p.transpose();
  }
  const Eigen::Matrix3d r = CameraRotation(c);
  const std::array<double, 3> centre = c.Centre();
  const Eigen::Vector3d on_axis =
      Eigen::Vector3d(centre[0], centre[1], centre[2]) + 2.0 * r.row(2).transpose();
  Eigen::Vector2d px;
  ASSERT_TRUE(ProjectPoint(c, on_axis, &px));
  EXPECT_NEAR(px.x(), truth.cx, 1e-6);
  EXPECT_NEAR(px.y(), truth.cy, 1e-6);
}

std::string RotationVector(const Camera& c) {
  const Eigen::AngleAxisd aa(CameraRotation(c));
  const Eigen::Vector3d w = aa.angle() * aa.axis();
  return List(w.data(), 3);
}

// anipose, Pose2Sim and FreeMoCap: [cam_N] sections named by `name`, the image
// size as `size`, K as `matrix`, 4 distortion terms, `rotation` a rotation
// vector, translation in metres; a [metadata] section that is not a camera.
TEST_F(CaptureFiles, ImportsAniposeToml) {
  Camera truth = TestCamera();
  truth.distortion[4] = 0;  // these files carry k1 k2 p1 p2
  std::ofstream toml(dir_ + "/Calib_board.toml");
  for (const char* name : {"cam01", "cam02"}) {
    toml << "[cam_" << name[4] << "]\nname = \"" << name << "\"\nsize = [ 640.0, 480.0,]\n"
         << "matrix = [ [ " << truth.fx << ", 0.0, " << truth.cx << ",], [ 0.0, " << truth.fy
         << ", " << truth.cy << ",], [ 0.0, 0.0, 1.0,],]\n"
         << "distortions = [ " << List(truth.distortion.data(), 4) << ",]\n"
         << "rotation = [ " << RotationVector(truth) << ",]\n"
         << "translation = [ " << List(truth.translation.data(), 3) << ",]\nfisheye = false\n\n";
  }
  toml << "[metadata]\nadjusted = false\nerror = 0.0\n";
  toml.close();
  StatusOr<ImportedCalibration> got = ImportCalibrationFiles({dir_ + "/Calib_board.toml"}, 1.0);
  ASSERT_TRUE(got.ok()) << got.status().ToString();
  EXPECT_EQ(got->format, "TOML");
  ASSERT_EQ(got->cameras.size(), 2u);
  EXPECT_EQ(got->cameras[0].name, "cam01");
  EXPECT_EQ(got->cameras[1].name, "cam02");
  for (const Camera& c : got->cameras) ExpectSameCamera(truth, c);
}

// EasyMocap: intri.yml and extri.yml complete each other; names are strings
// ("01"); R_<cam> is a rotation vector, Rot_<cam> the matrix.
TEST_F(CaptureFiles, ImportsEasyMocapIntriAndExtri) {
  const Camera truth = TestCamera();
  const double k[9] = {truth.fx, 0, truth.cx, 0, truth.fy, truth.cy, 0, 0, 1};
  auto matrix = [](const std::string& key, int rows, int cols, const std::string& data) {
    return key + ": !!opencv-matrix\n   rows: " + std::to_string(rows) +
           "\n   cols: " + std::to_string(cols) + "\n   dt: d\n   data: [ " + data + " ]\n";
  };
  std::ofstream(dir_ + "/intri.yml") << "%YAML:1.0\n---\nnames:\n   - \"01\"\n   - \"02\"\n"
                                     << matrix("K_01", 3, 3, List(k, 9))
                                     << matrix("dist_01", 1, 5, List(truth.distortion.data(), 5))
                                     << matrix("K_02", 3, 3, List(k, 9))
                                     << matrix("dist_02", 1, 5, List(truth.distortion.data(), 5))
                                     << "H_01: 480\nW_01: 640\nH_02: 480\nW_02: 640\n";
  std::ofstream(dir_ + "/extri.yml")
      << "%YAML:1.0\n---\nnames:\n   - \"01\"\n   - \"02\"\n"
      << matrix("R_01", 3, 1, RotationVector(truth))
      << matrix("T_01", 3, 1, List(truth.translation.data(), 3)) << matrix("R_02", 3, 1, "0, 0, 0")
      << matrix("Rot_02", 3, 3, List(truth.rotation.data(), 9))
      << matrix("T_02", 3, 1, List(truth.translation.data(), 3));
  StatusOr<ImportedCalibration> got =
      ImportCalibrationFiles({dir_ + "/intri.yml", dir_ + "/extri.yml"}, 1.0);
  ASSERT_TRUE(got.ok()) << got.status().ToString();
  EXPECT_EQ(got->format, "EasyMocap");
  ASSERT_EQ(got->cameras.size(), 2u);
  EXPECT_EQ(got->cameras[0].name, "01");
  for (const Camera& c : got->cameras) ExpectSameCamera(truth, c);
  // The intrinsics alone: a clear error about what is missing, naming the camera.
  StatusOr<ImportedCalibration> half = ImportCalibrationFiles({dir_ + "/intri.yml"}, 1.0);
  ASSERT_FALSE(half.ok());
  EXPECT_NE(half.status().message().find("camera 01: no rotation"), std::string::npos)
      << half.status().message();
  // The same file twice: a field given again is refused, naming both places.
  half = ImportCalibrationFiles({dir_ + "/extri.yml", dir_ + "/extri.yml"}, 1.0);
  ASSERT_FALSE(half.ok());
  EXPECT_NE(half.status().message().find("given again"), std::string::npos)
      << half.status().message();
}

// Qualisys .qca.txt: the camera's pose in the lab (mm, rotation row by row),
// intrinsics in 1/64 pixel on the sensor, the video window's offset, and the
// half turn about the camera's x axis between Qualisys and OpenCV axes.
TEST_F(CaptureFiles, ImportsQualisysQca) {
  const Camera truth = TestCamera();
  const Eigen::Matrix3d half_turn_x = Eigen::Vector3d(1, -1, -1).asDiagonal();
  const Eigen::Matrix3d m = half_turn_x * CameraRotation(truth);
  const std::array<double, 3> centre = truth.Centre();
  const int left = 16, top = 8;
  std::ofstream xml(dir_ + "/Calib.qca.txt");
  xml << "<?xml version='1.0' encoding='ASCII'?>\n<calibration type=\"regular\">\n<cameras>\n";
  for (const char* serial : {"cam01", "cam02"}) {
    char buf[1024];
    std::snprintf(buf, sizeof(buf),
                  "<camera active=\"1\" serial=\"%s\">\n"
                  "<fov_video bottom=\"%d\" left=\"%d\" right=\"%d\" top=\"%d\"/>\n"
                  "<transform r11=\"%.17g\" r12=\"%.17g\" r13=\"%.17g\" r21=\"%.17g\" "
                  "r22=\"%.17g\" r23=\"%.17g\" r31=\"%.17g\" r32=\"%.17g\" r33=\"%.17g\" "
                  "x=\"%.17g\" y=\"%.17g\" z=\"%.17g\"/>\n"
                  "<intrinsic centerPointU=\"%.17g\" centerPointV=\"%.17g\" "
                  "focalLengthU=\"%.17g\" focalLengthV=\"%.17g\" radialDistortion1=\"%.17g\" "
                  "radialDistortion2=\"%.17g\" radialDistortion3=\"%.17g\" "
                  "tangentalDistortion1=\"%.17g\" tangentalDistortion2=\"%.17g\"/>\n</camera>\n",
                  serial, top + 479, left, left + 639, top, m(0, 0), m(0, 1), m(0, 2), m(1, 0),
                  m(1, 1), m(1, 2), m(2, 0), m(2, 1), m(2, 2), centre[0] * 1000, centre[1] * 1000,
                  centre[2] * 1000, (truth.cx + left) * 64, (truth.cy + top) * 64, truth.fx * 64,
                  truth.fy * 64, truth.distortion[0], truth.distortion[1], truth.distortion[4],
                  truth.distortion[2], truth.distortion[3]);
    xml << buf;
  }
  xml << "<camera active=\"0\" serial=\"spare\"/>\n</cameras>\n</calibration>\n";
  xml.close();
  // --translation-unit does not apply: the format is in millimetres.
  StatusOr<ImportedCalibration> got = ImportCalibrationFiles({dir_ + "/Calib.qca.txt"}, 0.01);
  ASSERT_TRUE(got.ok()) << got.status().ToString();
  EXPECT_EQ(got->format, "Qualisys");
  EXPECT_EQ(got->up_axis, 'z');        // the lab frame Qualisys defines
  ASSERT_EQ(got->cameras.size(), 2u);  // the inactive camera is left out
  EXPECT_EQ(got->cameras[1].name, "cam02");
  for (const Camera& c : got->cameras) ExpectSameCamera(truth, c);
  // The same cameras again in another format (a take's folder holding the
  // lab's file and a converted one): their fields are named apart and would
  // merge without a clash, so the import refuses to mix them.
  std::ofstream(dir_ + "/Calib_converted.toml")
      << "[cam_1]\nname = \"cam01\"\nsize = [ 640.0, 480.0,]\n"
      << "matrix = [ [ " << truth.fx << ", 0.0, " << truth.cx << ",], [ 0.0, " << truth.fy << ", "
      << truth.cy << ",], [ 0.0, 0.0, 1.0,],]\ndistortions = [ 0.0, 0.0, 0.0, 0.0,]\n"
      << "rotation = [ " << RotationVector(truth) << ",]\n"
      << "translation = [ " << List(truth.translation.data(), 3) << ",]\n";
  StatusOr<ImportedCalibration> both =
      ImportCalibrationFiles({dir_ + "/Calib.qca.txt", dir_ + "/Calib_converted.toml"}, 1.0);
  ASSERT_FALSE(both.ok());
  EXPECT_NE(both.status().message().find("two calibrations describe camera cam01"),
            std::string::npos)
      << both.status().message();
  EXPECT_NE(both.status().message().find("(Qualisys) and"), std::string::npos);
  EXPECT_NE(both.status().message().find("(TOML); give one"), std::string::npos);
  // Broken files: a missing attribute, and not a calibration at all.
  std::ofstream(dir_ + "/broken.qca.txt")
      << "<calibration><cameras><camera serial=\"c\"><fov_video left=\"0\"/><transform/>"
      << "<intrinsic/></camera></cameras></calibration>";
  StatusOr<ImportedCalibration> bad = ImportCalibrationFiles({dir_ + "/broken.qca.txt"}, 1.0);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.status().message().find("camera c: a missing or non-numeric attribute"),
            std::string::npos)
      << bad.status().message();
  std::ofstream(dir_ + "/other.xml") << "<html><body/></html>";
  bad = ImportCalibrationFiles({dir_ + "/other.xml"}, 1.0);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.status().message().find("not a Qualisys calibration"), std::string::npos);
}

// Eight cameras on a ring 3.6 m out, alternately 1.3 and 2.0 m high, looking
// at the actor's middle (1 m up), each rolled about its optical axis by
// `roll_deg`; in a y-up world, or the same rig in a z-up one (the world turned
// a quarter about x, so that y goes to z).
std::vector<Camera> Ring(bool z_up, double roll_deg) {
  std::vector<Camera> cams;
  const Eigen::Matrix3d to_z = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).matrix();
  const Eigen::Matrix3d roll =
      Eigen::AngleAxisd(roll_deg * M_PI / 180, Eigen::Vector3d::UnitZ()).matrix();
  for (int i = 0; i < 8; ++i) {
    const double a = 2 * M_PI * i / 8;
    Camera c =
        LookAtCamera("c" + std::to_string(i), 640, 480, 600,
                     Eigen::Vector3d(3.6 * std::cos(a), i % 2 ? 2.0 : 1.3, 3.6 * std::sin(a)),
                     Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(0, 1, 0));
    Eigen::Matrix3d r = roll * CameraRotation(c);
    if (z_up) r = r * to_z.transpose();
    const Eigen::Vector3d centre = z_up ? Eigen::Vector3d(to_z * CameraCentre(c)) : CameraCentre(c);
    const Eigen::Vector3d t = -r * centre;
    for (int k = 0; k < 9; ++k) c.rotation[k] = r(k / 3, k % 3);
    for (int k = 0; k < 3; ++k) c.translation[k] = t[k];
    cams.push_back(c);
  }
  return cams;
}

TEST(UpAxis, UprightCamerasSayWhichAxisIsUp) {
  for (bool z_up : {false, true}) {
    const UpAxisEvidence e = InferUpAxis(Ring(z_up, 0));
    EXPECT_TRUE(e.found);
    EXPECT_EQ(e.axis, z_up ? 2 : 1);
    EXPECT_EQ(e.sign, 1);
    EXPECT_EQ(e.upright, 8u);
    EXPECT_FALSE(e.from_centres);
    EXPECT_GT(e.agreement, 0.9);
  }
  // Upside down: the image up points along -y.
  const UpAxisEvidence flipped = InferUpAxis(Ring(false, 180));
  EXPECT_TRUE(flipped.found);
  EXPECT_EQ(flipped.axis, 1);
  EXPECT_EQ(flipped.sign, -1);
}

TEST(UpAxis, RolledCamerasFallBackOnTheirRing) {
  // Portrait footage from cameras turned on their side: the image up lies
  // flat, the ring of centres still has a normal, on the side they look
  // down from.
  for (bool z_up : {false, true}) {
    const UpAxisEvidence e = InferUpAxis(Ring(z_up, 90));
    EXPECT_TRUE(e.found) << z_up;
    EXPECT_TRUE(e.from_centres) << z_up;
    EXPECT_EQ(e.axis, z_up ? 2 : 1) << z_up;
    EXPECT_EQ(e.sign, 1) << z_up;
    EXPECT_EQ(e.upright, 0u) << z_up;
  }
  // Two rolled cameras facing each other: their image ups cancel, and two
  // centres span no ring; nothing found.
  const std::vector<Camera> ring = Ring(true, 90);
  EXPECT_FALSE(InferUpAxis({ring[0], ring[4]}).found);
}

TEST(UpAxis, TheFormatsAxisOrTheCamerasAndAWarningWhereTheyDisagree) {
  const std::vector<Camera> z_rig = Ring(true, 0);
  UpAxisChoice c = ChooseUpAxis("auto", 'z', "Qualisys", z_rig);
  EXPECT_EQ(c.axis, 'z');
  EXPECT_NE(c.reason.find("Qualisys"), std::string::npos) << c.reason;
  EXPECT_TRUE(c.warning.empty()) << c.warning;
  c = ChooseUpAxis("auto", 0, "TOML", z_rig);
  EXPECT_EQ(c.axis, 'z');
  EXPECT_NE(c.reason.find("from the cameras"), std::string::npos) << c.reason;
  EXPECT_TRUE(c.warning.empty()) << c.warning;
  EXPECT_EQ(ChooseUpAxis("auto", 0, "TOML", Ring(false, 0)).axis, 'y');
  // Told otherwise than the cameras stand: taken, with a warning.
  c = ChooseUpAxis("y", 0, "TOML", z_rig);
  EXPECT_EQ(c.axis, 'y');
  EXPECT_NE(c.warning.find("+z"), std::string::npos) << c.warning;
  c = ChooseUpAxis("auto", 'z', "Qualisys", Ring(false, 0));
  EXPECT_EQ(c.axis, 'z');
  EXPECT_NE(c.warning.find("+y"), std::string::npos) << c.warning;
  // An upside-down rig cannot be said in capture.json: y, with a warning.
  c = ChooseUpAxis("auto", 0, "TOML", Ring(false, 180));
  EXPECT_EQ(c.axis, 'y');
  EXPECT_NE(c.reason.find("-y"), std::string::npos) << c.reason;
  EXPECT_FALSE(c.warning.empty());
  // A loaded capture (fvv's y-up world) whose cameras do not stand upright.
  std::vector<CaptureCamera> loaded(8);
  for (int i = 0; i < 8; ++i) loaded[size_t(i)].calibration = Ring(false, 0)[size_t(i)];
  EXPECT_EQ(UprightWarning(loaded, 'y'), "");
  for (int i = 0; i < 8; ++i) loaded[size_t(i)].calibration = z_rig[size_t(i)];
  const std::string w = UprightWarning(loaded, 'y');
  EXPECT_NE(w.find("+z"), std::string::npos) << w;
  EXPECT_NE(w.find("--up"), std::string::npos) << w;
}

// Frames of another size than the calibration's window: their size is taken,
// with a note saying by how much; a principal point outside them is an error.
TEST(CalibrationImport, FrameSizeWinsWithANoteAndThePrincipalPointMustLieInside) {
  Camera c = TestCamera();
  std::string note;
  ASSERT_TRUE(FitImageSize(640, 480, &c, &note).ok());
  EXPECT_TRUE(note.empty()) << note;
  ASSERT_TRUE(FitImageSize(632, 480, &c, &note).ok());
  EXPECT_EQ(c.width, 632u);
  EXPECT_NE(note.find("640x480, its frames are 632x480 (-8 x +0 pixels)"), std::string::npos)
      << note;
  EXPECT_EQ(c.cx, 322.5);
  Status s = FitImageSize(320, 240, &c, &note);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("principal point (322.5, 236.0) lies outside the 320x240 image"),
            std::string::npos)
      << s.message();
}

}  // namespace fvv
