// Tests that film a synthetic capture once for their whole suite: `Suite`
// names the capture's temporary directory and gives its options
// (static SynthOptions Options()); the capture is removed afterwards. Streams
// encoded from it are made once per suite too, by name.
#ifndef FVV_TESTS_SYNTH_CAPTURE_FIXTURE_H_
#define FVV_TESTS_SYNTH_CAPTURE_FIXTURE_H_

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <map>
#include <string>

#include "encoder/encode/encoder.h"
#include "tools/synth/synth.h"
#include "tools/synth/view_score.h"

namespace fvv {

template <class Suite>
class SynthCaptureFixture : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = ::testing::TempDir() + "/" + Suite::kName + "_" + std::to_string(getpid());
    std::system(("rm -rf '" + dir_ + "'").c_str());
    synth_ = Suite::Options();
    synth_.output_dir = dir_ + "/cap";
    status_ = RunSynth(synth_).status();
  }
  static void TearDownTestSuite() { std::system(("rm -rf '" + dir_ + "'").c_str()); }
  void SetUp() override { ASSERT_TRUE(status_.ok()) << status_.ToString(); }

  // Encoding with the capture's true poses (what measures the shape alone),
  // at a 512 atlas.
  static EncoderSettings TruePoses() {
    EncoderSettings s;
    s.poses = synth_.output_dir;
    s.atlas_size = 512;
    return s;
  }
  // The capture encoded into `name` in the suite's directory, once: a later
  // call with the same name (and so the same settings) returns the first
  // encode's summary.
  static StatusOr<EncodeSummary> Encode(const std::string& name, const EncoderSettings& s) {
    const auto it = encoded_.find(name);
    if (it != encoded_.end()) return it->second;
    StatusOr<EncodeSummary> r = EncodeCapture(synth_.output_dir, dir_ + "/" + name, s);
    if (r.ok()) encoded_.emplace(name, *r);
    return r;
  }
  // Renderer II's PSNR of stream `name` in held-out camera 0 at `frame`.
  static StatusOr<double> HeldOutPsnr(const std::string& name, uint32_t frame) {
    return HeldOutStreamPsnr(dir_ + "/" + name, synth_.output_dir, 0, frame);
  }

  static inline std::string dir_;
  static inline SynthOptions synth_;
  static inline Status status_;
  static inline std::map<std::string, EncodeSummary> encoded_;
};

}  // namespace fvv

#endif  // FVV_TESTS_SYNTH_CAPTURE_FIXTURE_H_
