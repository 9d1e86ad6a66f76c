// `fvv decode`: what the decoder library returns for a stream, written as files
// (the way to inspect a stream and to compare decoders, like djxl / opj_decompress).
#ifndef FVV_TOOLS_FVV_DECODE_COMMAND_H_
#define FVV_TOOLS_FVV_DECODE_COMMAND_H_

#include <CLI/CLI.hpp>

namespace fvv {

void AddDecodeCommand(CLI::App* app, int* exit_code);

}  // namespace fvv

#endif  // FVV_TOOLS_FVV_DECODE_COMMAND_H_
