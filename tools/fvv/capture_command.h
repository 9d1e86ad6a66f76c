// `fvv synth` (synthetic captures) and `fvv capture ...` (capture directories:
// check, contact sheet, calibration import).
#ifndef FVV_TOOLS_FVV_CAPTURE_COMMAND_H_
#define FVV_TOOLS_FVV_CAPTURE_COMMAND_H_

#include <CLI/CLI.hpp>

namespace fvv {

void AddCaptureCommands(CLI::App* app, int* exit_code);

}  // namespace fvv

#endif  // FVV_TOOLS_FVV_CAPTURE_COMMAND_H_
