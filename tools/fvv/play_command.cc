#include "tools/fvv/play_command.h"

#include <cstdio>
#include <memory>

#if FVV_HAVE_PLAYER
#include "tools/play/player.h"
#endif

namespace fvv {

void AddPlayCommand(CLI::App* app, int* exit_code) {
#if FVV_HAVE_PLAYER
  auto o = std::make_shared<PlayerOptions>();
  CLI::App* p = app->add_subcommand(
      "play", "Play a .fvv stream in a window (Renderer II, free viewpoint, real-time decoding)");
  p->footer(PlayerControlsHelp());
  p->add_option("file", o->input, ".fvv stream")->required()->check(CLI::ExistingFile);
  p->add_option("--width", o->width, "Window width")->capture_default_str();
  p->add_option("--height", o->height, "Window height")->capture_default_str();
  p->add_option("--exponent", o->exponent, "Initial blend exponent")->capture_default_str();
  p->add_option("--floor", o->floor_share,
                "Quality floor: the share of each GOP's texture bytes decoded under any load "
                "(below it playback slows down instead)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  p->add_option("--seconds", o->seconds,
                "Play this many seconds, print a summary and exit (benchmarks, tests)")
      ->check(CLI::PositiveNumber);
  p->add_flag("--all-cameras", o->all_cameras,
              "Decode every camera's texture, not only the cameras the view blends (key A)");
  p->add_option("--screenshot", o->screenshot,
                "With --seconds: save the last frame drawn, HUD included, as PNG");
  p->callback([o, exit_code] {
    if (!o->screenshot.empty() && o->seconds <= 0) {
      std::fprintf(stderr, "fvv: --screenshot needs --seconds S\n");
      *exit_code = 1;
      return;
    }
    *exit_code = RunPlayer(*o);
  });
#else
  CLI::App* p = app->add_subcommand("play", "(not built: configure with FVV_BUILD_PLAYER=ON)");
  p->allow_extras();
  p->callback([exit_code] {
    std::fprintf(stderr, "fvv: this fvv was built without the player (FVV_BUILD_PLAYER=OFF)\n");
    *exit_code = 1;
  });
#endif
}

}  // namespace fvv
