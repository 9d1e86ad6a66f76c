// `fvv join`: the shards of one take (fvv encode --shard K/N) into one stream.
#ifndef FVV_TOOLS_FVV_JOIN_COMMAND_H_
#define FVV_TOOLS_FVV_JOIN_COMMAND_H_

#include <CLI/CLI.hpp>

namespace fvv {

void AddJoinCommand(CLI::App* app, int* exit_code);

}  // namespace fvv

#endif  // FVV_TOOLS_FVV_JOIN_COMMAND_H_
