// `fvv play`: the interactive player (available when built with FVV_BUILD_PLAYER).
#ifndef FVV_TOOLS_FVV_PLAY_COMMAND_H_
#define FVV_TOOLS_FVV_PLAY_COMMAND_H_

#include <CLI/CLI.hpp>

namespace fvv {

void AddPlayCommand(CLI::App* app, int* exit_code);

}  // namespace fvv

#endif  // FVV_TOOLS_FVV_PLAY_COMMAND_H_
