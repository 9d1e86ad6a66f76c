#include "tools/fvv/conform_command.h"

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "conformance/lib/runner.h"

namespace fvv {
namespace {

struct ConformArgs {
  std::vector<std::string> roots{"conformance/cases"};
  std::vector<std::string> only;
  std::string decoder;
  bool any_error = false, list = false, bless = false, force = false, quiet = false,
       add_outputs = false;
  std::vector<uint64_t> budgets;
  unsigned timeout = 300, threads = 2;
  int max_level = 0;
};

bool Selected(const ConformanceCase& c, const std::vector<std::string>& only) {
  if (only.empty()) return true;
  for (const std::string& s : only) {
    if (c.name.find(s) != std::string::npos) return true;
  }
  return false;
}

std::string Join(const std::vector<std::string>& v, const char* sep) {
  std::string out;
  for (size_t i = 0; i < v.size(); ++i) out += (i ? sep : "") + v[i];
  return out;
}

int RunConform(const ConformArgs& a) {
  if (!a.decoder.empty()) {
    if (Status s = CheckDecoderTemplate(a.decoder); !s.ok()) {
      std::fprintf(stderr, "fvv conform: %s\n", s.message().c_str());
      return 2;
    }
  }
  std::vector<ConformanceCase> cases;
  for (const std::string& root : a.roots) {
    auto dirs = FindCaseDirs(root);
    if (!dirs.ok()) {
      std::fprintf(stderr, "fvv conform: %s\n", dirs.status().ToString().c_str());
      return 2;
    }
    for (const std::string& dir : *dirs) {
      auto c = LoadCase(dir);
      if (!c.ok()) {
        std::fprintf(stderr, "fvv conform: %s\n", c.status().ToString().c_str());
        return 2;
      }
      if (Selected(*c, a.only)) cases.push_back(std::move(c).value());
    }
  }
  if (cases.empty()) {
    std::fprintf(stderr, "fvv conform: no cases found (a case is a directory with test.json)\n");
    return 2;
  }
  if (a.list) {
    std::printf("| case | expect | level | coding tools | spec sections | what it checks |\n");
    std::printf("|---|---|---|---|---|---|\n");
    for (const ConformanceCase& c : cases) {
      std::printf("| %s | %s | %d | %s | %s | %s |\n", c.name.c_str(),
                  c.expect_error ? StatusCodeName(c.error) : "decode", c.level,
                  Join(c.tools, " ").c_str(), Join(c.spec_sections, " ").c_str(),
                  c.description.c_str());
    }
    return 0;
  }
  if (a.bless) {
    for (ConformanceCase& c : cases) {
      if (Status s = BlessCase(&c, a.budgets, a.force); !s.ok()) {
        std::fprintf(stderr, "fvv conform: %s\n", s.ToString().c_str());
        return 1;
      }
      std::printf("blessed %s\n", c.name.c_str());
    }
    return 0;
  }
  if (a.add_outputs) {
    for (ConformanceCase& c : cases) {
      StatusOr<size_t> added = AddNewOutputs(&c);
      if (!added.ok()) {
        std::fprintf(stderr, "fvv conform: %s\n", added.status().ToString().c_str());
        return 1;
      }
      if (*added) std::printf("%-40s %zu output hashes added\n", c.name.c_str(), *added);
    }
    return 0;
  }
  RunOptions options;
  options.decoder = a.decoder;
  options.any_error = a.any_error;
  options.timeout_seconds = a.timeout;
  options.threads = a.threads;
  options.max_level = a.max_level;
  int passed = 0, failed = 0, beyond = 0;
  for (const ConformanceCase& c : cases) {
    const CaseResult r = RunCase(c, options);
    r.passed ? ++passed : r.beyond_claim ? ++beyond : ++failed;
    if (!r.passed || !a.quiet) {
      std::printf("%s  %-40s %6.2f s%s%s\n",
                  r.passed         ? "PASS"
                  : r.beyond_claim ? "BEYOND"
                                   : "FAIL",
                  r.name.c_str(), r.seconds, r.detail.empty() ? "" : "  ", r.detail.c_str());
      std::fflush(stdout);
    }
  }
  std::printf("%d passed, %d failed%s (%s)\n", passed, failed,
              beyond ? (", " + std::to_string(beyond) + " beyond the decoder's claim").c_str() : "",
              a.decoder.empty() ? "reference decoder: random-access and streaming readers"
                                : a.decoder.c_str());
  return failed == 0 ? 0 : 1;
}

}  // namespace

void AddConformCommand(CLI::App* app, int* exit_code) {
  auto args = std::make_shared<ConformArgs>();
  CLI::App* c = app->add_subcommand(
      "conform",
      "Run the conformance suite: decode every case's stream and compare the SHA-256 of each "
      "output file (SPEC.md Annex B) in full and at each truncation budget, or check that an "
      "invalid stream is rejected with its status code. Prints a line per case and \"N passed, "
      "N failed\"; exit status 0 when all pass, 1 when any fails, 2 on usage errors");
  c->add_option("dirs", args->roots,
                "Suite directories or single cases (a directory with test.json)")
      ->capture_default_str();
  c->add_option("--case", args->only, "Only cases whose name contains this text (repeatable)");
  c->add_option("--decoder", args->decoder,
                "Check an external decoder: a shell command with {stream}, {out} (an empty "
                "directory it fills with the conformance output) and {bytes} (budget per "
                "fragment, 0 = whole); it exits 0, or with the status code when it rejects a "
                "stream. E.g. 'fvv decode {stream} -o {out} --bytes {bytes} --format "
                "conformance'");
  c->add_flag("--any-error", args->any_error,
              "With --decoder: accept any non-zero exit for invalid streams, not only the "
              "expected status code");
  c->add_option("--timeout", args->timeout, "Seconds an external decoder may take per run")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  c->add_option("--max-level", args->max_level,
                "The decoder's claim (SPEC.md 5.1): cases whose stream declares a higher level "
                "are not run and are reported as beyond it (BEYOND), neither passed nor failed")
      ->check(CLI::Range(1, 4));
  c->add_option("--threads", args->threads, "Threads of the reference decoder")
      ->check(CLI::Range(1u, 64u))
      ->capture_default_str();
  c->add_flag("--list", args->list, "List the cases as a Markdown table (tools, spec sections)");
  c->add_flag("--bless", args->bless,
              "Fill in the expected outputs of new cases from the reference decoder (a case's "
              "test.json gives name, format_version and expect; see conformance/README.md)");
  c->add_option("--budgets", args->budgets,
                "With --bless: truncation budgets (bytes per fragment) to record besides whole "
                "streams")
      ->delimiter(',');
  c->add_flag("--force", args->force, "With --bless: overwrite existing expectations");
  c->add_flag("--add-outputs", args->add_outputs,
              "Add to released cases the hashes of output files the spec's Annex B added since "
              "(every hash they record must still match)");
  c->add_flag("-q,--quiet", args->quiet, "Print only failures and the summary");
  c->callback([args, exit_code] { *exit_code = RunConform(*args); });
}

}  // namespace fvv
