// `fvv track`: marker-free motion capture of a capture directory (silhouettes,
// initialisation, tracking), with joint errors against ground truth.
#ifndef FVV_TOOLS_FVV_TRACK_COMMAND_H_
#define FVV_TOOLS_FVV_TRACK_COMMAND_H_

#include <CLI/CLI.hpp>

namespace fvv {

void AddTrackCommand(CLI::App* app, int* exit_code);

}  // namespace fvv

#endif  // FVV_TOOLS_FVV_TRACK_COMMAND_H_
