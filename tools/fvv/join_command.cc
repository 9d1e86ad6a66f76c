#include "tools/fvv/join_command.h"

#include <cstdio>
#include <memory>

#include "container/stream_join.h"

namespace fvv {

void AddJoinCommand(CLI::App* app, int* exit_code) {
  struct Args {
    std::vector<std::string> parts;
    std::string output;
    bool quiet = false;
  };
  auto a = std::make_shared<Args>();
  CLI::App* j = app->add_subcommand(
      "join", "Join the shards of one take (fvv encode --shard K/N) into one stream");
  j->footer(
      "The parts may come in any order. They must agree on everything but their frames "
      "(header, cameras, model, motion steps, metadata) and together hold every frame of the "
      "take; the error names a missing or mismatched part. The motion track's statistics are "
      "measured again over the whole take. With the poses and prepared take shared, the result "
      "is byte for byte what one fvv encode of the take writes (docs/scale-out.md).\n"
      "Example: fvv join part_*.fvv -o take.fvv");
  j->add_option("parts", a->parts, "The shards' .fvv files")->required()->check(CLI::ExistingFile);
  j->add_option("-o,--output", a->output, "The joined .fvv to write")->required();
  j->add_flag("-q,--quiet", a->quiet, "No progress");
  j->callback([a, exit_code] {
    std::function<void(const std::string&)> progress;
    if (!a->quiet) progress = [](const std::string& l) { std::fprintf(stderr, "%s\n", l.c_str()); };
    StatusOr<JoinSummary> r = JoinShards(a->parts, a->output, progress);
    if (!r.ok()) {
      std::fprintf(stderr, "fvv: %s\n", r.status().ToString().c_str());
      *exit_code = 1;
      return;
    }
    std::printf("joined %u parts: %s, %u frames, %u fragments, %llu bytes%s\n", r->parts,
                a->output.c_str(), r->frames, r->fragments, (unsigned long long)r->bytes,
                r->motion_recoded ? " (motion track recoded with the take's statistics)" : "");
    *exit_code = 0;
  });
}

}  // namespace fvv
