// `fvv info` (inspect a .fvv stream) and `fvv sample` (write a synthetic one).
#ifndef FVV_TOOLS_FVV_STREAM_COMMAND_H_
#define FVV_TOOLS_FVV_STREAM_COMMAND_H_

#include <CLI/CLI.hpp>

namespace fvv {

void AddStreamCommands(CLI::App* app, int* exit_code);

}  // namespace fvv

#endif  // FVV_TOOLS_FVV_STREAM_COMMAND_H_
