// Runs conformance cases against the reference decoder (in process, through
// both the random-access and the streaming reader) or against an external
// decoder driven through a command template, and blesses new cases.
#ifndef FVV_CONFORMANCE_LIB_RUNNER_H_
#define FVV_CONFORMANCE_LIB_RUNNER_H_

#include <string>
#include <vector>

#include "codec/base/status.h"
#include "conformance/lib/conformance_case.h"

namespace fvv {

struct RunOptions {
  // Empty: the reference decoder in process. Otherwise a shell command with
  // {stream} (input file), {out} (an empty directory for the conformance
  // output) and optionally {bytes} (budget per fragment, 0 = whole) replaced
  // by shell-quoted values. The decoder exits 0 after writing the output, and
  // with the error code of SPEC.md section 10 when it rejects a stream.
  std::string decoder;
  bool any_error = false;          // external: any non-zero exit counts as a rejection
  unsigned timeout_seconds = 300;  // external: per decoder run; longer is a hang
  unsigned threads = 2;            // reference decoder
  std::string work_dir = "/tmp";   // where external outputs go (removed after)
  // The decoder's claim (SPEC.md 5.1): cases whose stream declares a higher
  // level are beyond it, reported as such and not run; 0 = every level.
  int max_level = 0;
};

struct CaseResult {
  std::string name;
  bool passed = false;
  bool beyond_claim = false;  // not run: its level is above RunOptions::max_level
  std::string detail;         // why it failed; notes when it passed
  double seconds = 0;
};

CaseResult RunCase(const ConformanceCase& c, const RunOptions& options);

// Checks a decoder command template (placeholders, quoting).
Status CheckDecoderTemplate(const std::string& decoder);

// Fills in a case's expected outputs from the reference decoder: the stream's
// hash, the budget-independent outputs and the samples at every budget
// listed (0 = whole is always first). Refuses a case that already has
// expectations unless `force` (released cases never change).
Status BlessCase(ConformanceCase* c, const std::vector<uint64_t>& budgets, bool force);
// A released valid case gains the hashes of output files Annex B added after
// it was made (at each of its budgets), once every hash it records is
// confirmed unchanged; saved. Returns how many it added.
StatusOr<size_t> AddNewOutputs(ConformanceCase* c);

}  // namespace fvv

#endif  // FVV_CONFORMANCE_LIB_RUNNER_H_
