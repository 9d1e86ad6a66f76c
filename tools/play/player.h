// `fvv play`: the interactive player (GLFW window, Renderer II, real-time
// quality control).
#ifndef FVV_TOOLS_PLAY_PLAYER_H_
#define FVV_TOOLS_PLAY_PLAYER_H_

#include <string>

#include "container/geometric_visibility.h"
#include "player/playback/playback_controller.h"

namespace fvv {

struct PlayerOptions {
  std::string input;
  int width = 1280, height = 720;
  float exponent = float(geometric_visibility::kViewExponent);
  double floor_share = PlaybackController::kDefaultFloorShare;  // decoded under any load
  bool loop = true;
  bool all_cameras = false;  // decode every camera, not only those the view blends
  double seconds = 0;        // > 0: play this long, print a summary and exit (benchmarks, tests)
  std::string screenshot;    // with seconds: the last frame drawn (HUD included), as PNG
};

// The keys and mouse controls, for --help.
const char* PlayerControlsHelp();
// Runs until the window closes; returns the process exit status.
int RunPlayer(const PlayerOptions& options);

}  // namespace fvv

#endif  // FVV_TOOLS_PLAY_PLAYER_H_
