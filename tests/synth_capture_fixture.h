// Tests that film a synthetic capture once for their whole suite: `Suite`
// names the capture's temporary directory and gives its options
// (static SynthOptions Options()); the capture is removed afterwards.
#ifndef FVV_TESTS_SYNTH_CAPTURE_FIXTURE_H_
#define FVV_TESTS_SYNTH_CAPTURE_FIXTURE_H_

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <string>

#include "tools/synth/synth.h"

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

  static inline std::string dir_;
  static inline SynthOptions synth_;
  static inline Status status_;
};

}  // namespace fvv

#endif  // FVV_TESTS_SYNTH_CAPTURE_FIXTURE_H_
