// `fvv block ...`: the texture codec on its own, on a user's images.
#ifndef FVV_TOOLS_FVV_BLOCK_COMMAND_H_
#define FVV_TOOLS_FVV_BLOCK_COMMAND_H_

#include <CLI/CLI.hpp>

namespace fvv {

// Adds `block encode`, `block decode` and `block sample` to the app; each sets
// *exit_code when it runs.
void AddBlockCommands(CLI::App* app, int* exit_code);

}  // namespace fvv

#endif  // FVV_TOOLS_FVV_BLOCK_COMMAND_H_
