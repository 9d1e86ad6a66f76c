// A conformance case: a committed stream and its test.json (conformance/README.md):
// what a decoder must output for it (SHA-256 of every file of the conformance
// output, SPEC.md Annex B, in full and at listed truncation budgets), or the
// error code it must stop with.
#ifndef FVV_CONFORMANCE_LIB_CONFORMANCE_CASE_H_
#define FVV_CONFORMANCE_LIB_CONFORMANCE_CASE_H_

#include <cstdint>
#include <string>
#include <vector>

#include "codec/base/status.h"
#include "conformance/lib/reference_output.h"

namespace fvv {

struct BudgetExpectation {
  uint64_t bytes_per_fragment = 0;  // 0 = whole streams
  OutputHashes yuv;                 // yuv_*.bin at this budget
  OutputHashes rgb;                 // rgb_*.bin at this budget
  OutputHashes surface;             // surface_*.bin at this budget (optional outputs)
};

struct ConformanceCase {
  std::string dir;  // the case directory (test.json and the stream)
  std::string name, description;
  // The stream header's own fields (also where they are what makes the case
  // invalid).
  int format_version = 1, profile = 1, level = 1;
  // The format version a decoder must implement to be held to the case: a
  // decoder of an older version skips it (it cannot know the tool whose misuse
  // the case pins). test.json's "decoder_version", when it differs from a
  // valid format_version; else format_version.
  int decoder_version = 1;
  std::vector<std::string> tools, spec_sections;
  std::string stream = "stream.fvv";  // relative to dir
  std::string stream_sha256;          // the released stream's bytes never change

  bool expect_error = false;
  // Valid streams: files that do not depend on the budget (motion, masks,
  // vertex visibility), then the samples per budget (the first is 0 = whole).
  OutputHashes fixed;
  std::vector<BudgetExpectation> budgets;
  // Invalid streams, and the budget they are decoded at (0 = whole streams; a
  // budget that ends inside a chunked fragment's head is the error).
  StatusCode error = StatusCode::kOk;
  uint64_t error_bytes_per_fragment = 0;

  std::string stream_path() const { return dir + "/" + stream; }
  bool blessed() const { return expect_error || !budgets.empty(); }
};

StatusOr<ConformanceCase> LoadCase(const std::string& dir);
Status SaveCase(const ConformanceCase& c);  // writes dir/test.json (temp file, then rename)

// Every case directory (one holding a test.json) under `root`, or `root`
// itself when it is one; sorted by path.
StatusOr<std::vector<std::string>> FindCaseDirs(const std::string& root);

}  // namespace fvv

#endif  // FVV_CONFORMANCE_LIB_CONFORMANCE_CASE_H_
