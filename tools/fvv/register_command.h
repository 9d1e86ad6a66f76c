// `fvv capture register`: poses and proportions from feature points,
// written as a poses.json the encoder takes (--poses).
#ifndef FVV_TOOLS_FVV_REGISTER_COMMAND_H_
#define FVV_TOOLS_FVV_REGISTER_COMMAND_H_

#include <CLI/CLI.hpp>

namespace fvv {

// Adds `register` under the `capture` subcommand.
void AddRegisterCommand(CLI::App* capture, int* exit_code);

}  // namespace fvv

#endif  // FVV_TOOLS_FVV_REGISTER_COMMAND_H_
