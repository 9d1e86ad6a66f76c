// The fvv command-line tool.
#include <CLI/CLI.hpp>
#include <cstdio>

#include "encoder/cli/block_command.h"
#include "encoder/cli/capture_command.h"
#include "encoder/cli/conform_command.h"
#include "encoder/cli/decode_command.h"
#include "encoder/cli/encode_command.h"
#include "encoder/cli/play_command.h"
#include "encoder/cli/render_command.h"
#include "encoder/cli/stream_command.h"
#include "encoder/cli/track_command.h"

int main(int argc, char** argv) {
  CLI::App app{"fvv: free-viewpoint video of human actors (codec SDK tools)"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "fvv 0.1.0");
  int exit_code = 0;
  fvv::AddCaptureCommands(&app, &exit_code);
  fvv::AddTrackCommand(&app, &exit_code);
  fvv::AddEncodeCommand(&app, &exit_code);
  fvv::AddStreamCommands(&app, &exit_code);
  fvv::AddDecodeCommand(&app, &exit_code);
  fvv::AddConformCommand(&app, &exit_code);
  fvv::AddRenderCommand(&app, &exit_code);
  fvv::AddPlayCommand(&app, &exit_code);
  fvv::AddBlockCommands(&app, &exit_code);
  CLI11_PARSE(app, argc, argv);
  return exit_code;
}
