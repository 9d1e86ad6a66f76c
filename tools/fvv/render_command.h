// `fvv render`: headless rendering (OSMesa) of a stream with Renderer II.
#ifndef FVV_TOOLS_FVV_RENDER_COMMAND_H_
#define FVV_TOOLS_FVV_RENDER_COMMAND_H_

#include <CLI/CLI.hpp>

namespace fvv {

void AddRenderCommand(CLI::App* app, int* exit_code);

}  // namespace fvv

#endif  // FVV_TOOLS_FVV_RENDER_COMMAND_H_
