// `fvv encode`: a capture directory (or poses and atlas textures computed
// elsewhere) to a .fvv stream, with a summary of sizes, quality and speed.
#ifndef FVV_TOOLS_FVV_ENCODE_COMMAND_H_
#define FVV_TOOLS_FVV_ENCODE_COMMAND_H_

#include <CLI/CLI.hpp>

namespace fvv {

void AddEncodeCommand(CLI::App* app, int* exit_code);

}  // namespace fvv

#endif  // FVV_TOOLS_FVV_ENCODE_COMMAND_H_
