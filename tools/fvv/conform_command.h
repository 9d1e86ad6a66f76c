// `fvv conform`: runs the conformance suite (conformance/README.md) against the
// reference decoder or an external one, lists its cases, and blesses new ones.
#ifndef FVV_TOOLS_FVV_CONFORM_COMMAND_H_
#define FVV_TOOLS_FVV_CONFORM_COMMAND_H_

#include <CLI/CLI.hpp>

namespace fvv {

void AddConformCommand(CLI::App* app, int* exit_code);

}  // namespace fvv

#endif  // FVV_TOOLS_FVV_CONFORM_COMMAND_H_
