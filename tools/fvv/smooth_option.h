// The --smooth option of the commands that track (fvv track, fvv encode).
#ifndef FVV_TOOLS_FVV_SMOOTH_OPTION_H_
#define FVV_TOOLS_FVV_SMOOTH_OPTION_H_

#include <CLI/CLI.hpp>

namespace fvv {

inline void AddSmoothOption(CLI::App* app, double* sigma_frames) {
  app->add_option("--smooth", *sigma_frames,
                  "Smooth tracked poses over time: Gaussian sigma in frames (0: off; up to 16)")
      ->check(CLI::Range(0.0, 16.0))
      ->capture_default_str();
}

}  // namespace fvv

#endif  // FVV_TOOLS_FVV_SMOOTH_OPTION_H_
