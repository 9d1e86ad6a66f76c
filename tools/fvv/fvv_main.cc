// The fvv command-line tool.
#include <CLI/CLI.hpp>
#include <cstdio>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "encoder/io/child_process.h"
#include "tools/fvv/block_command.h"
#include "tools/fvv/capture_command.h"
#include "tools/fvv/conform_command.h"
#include "tools/fvv/decode_command.h"
#include "tools/fvv/encode_command.h"
#include "tools/fvv/export_command.h"
#include "tools/fvv/join_command.h"
#include "tools/fvv/play_command.h"
#include "tools/fvv/render_command.h"
#include "tools/fvv/stream_command.h"
#include "tools/fvv/track_command.h"

int main(int argc, char** argv) {
#if defined(__GLIBC__)
  // The codec allocates and frees buffers of several MB per GOP and channel
  // (planes, transform scratch, trial decodes). By default glibc serves each
  // from a fresh mmap and trims freed heap back to the system, so every one
  // is page-faulted in again (docs/encoder.md, "Speed"). The libraries leave
  // allocation to their host.
  mallopt(M_MMAP_THRESHOLD, 256 << 20);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
#endif
  // Ctrl-C, a scheduler's SIGTERM or a closed terminal take the ffmpeg
  // children along (a capture's video decoders, a render's encoder).
  fvv::KillChildrenOnTerminatingSignals();
  CLI::App app{"fvv: free-viewpoint video of human actors (codec SDK tools)"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "fvv 0.1.0");
  int exit_code = 0;
  fvv::AddCaptureCommands(&app, &exit_code);
  fvv::AddTrackCommand(&app, &exit_code);
  fvv::AddEncodeCommand(&app, &exit_code);
  fvv::AddJoinCommand(&app, &exit_code);
  fvv::AddExportCommand(&app, &exit_code);
  fvv::AddStreamCommands(&app, &exit_code);
  fvv::AddDecodeCommand(&app, &exit_code);
  fvv::AddConformCommand(&app, &exit_code);
  fvv::AddRenderCommand(&app, &exit_code);
  fvv::AddPlayCommand(&app, &exit_code);
  fvv::AddBlockCommands(&app, &exit_code);
  CLI11_PARSE(app, argc, argv);
  return exit_code;
}
