// `fvv capture calibrate-colour`: each camera's colour gain from the actor's
// surface as the cameras see it over a span of frames, written into
// capture.json (encoder/shape/colour_calibration.h).
#ifndef FVV_TOOLS_FVV_CALIBRATE_COLOUR_COMMAND_H_
#define FVV_TOOLS_FVV_CALIBRATE_COLOUR_COMMAND_H_

#include <CLI/CLI.hpp>

namespace fvv {

// Adds `calibrate-colour` under the `capture` subcommand.
void AddCalibrateColourCommand(CLI::App* capture, int* exit_code);

}  // namespace fvv

#endif  // FVV_TOOLS_FVV_CALIBRATE_COLOUR_COMMAND_H_
