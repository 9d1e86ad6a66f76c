// `fvv export`: a stream's actor as glTF 2.0 (.glb / .gltf) or BVH.
#ifndef FVV_TOOLS_FVV_EXPORT_COMMAND_H_
#define FVV_TOOLS_FVV_EXPORT_COMMAND_H_

#include <CLI/CLI.hpp>

namespace fvv {

void AddExportCommand(CLI::App* app, int* exit_code);

}  // namespace fvv

#endif  // FVV_TOOLS_FVV_EXPORT_COMMAND_H_
