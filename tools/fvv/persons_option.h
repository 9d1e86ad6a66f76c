// The --persons and --models options of the commands that read silhouettes
// from the person network (fvv track, fvv encode).
#ifndef FVV_TOOLS_FVV_PERSONS_OPTION_H_
#define FVV_TOOLS_FVV_PERSONS_OPTION_H_

#include <CLI/CLI.hpp>
#include <string>

#include "encoder/track/track_capture.h"

namespace fvv {

inline void AddPersonsOptions(CLI::App* app, const std::string& what, std::string* persons,
                              std::string* models) {
  app->add_option("--persons", *persons,
                  "Silhouettes from the pretrained person network (its mask of the actor), " +
                      what +
                      ": auto (where the capture has neither silhouettes nor plates and the "
                      "models are installed), on, off")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "on", "off"}));
  app->add_option("--models", *models,
                  "Directory of the person models (default: $FVV_MODEL_DIR or "
                  "~/.cache/fvv/models)");
}

inline TrackCaptureOptions::Persons PersonsSetting(const std::string& persons) {
  return persons == "on"    ? TrackCaptureOptions::Persons::kOn
         : persons == "off" ? TrackCaptureOptions::Persons::kOff
                            : TrackCaptureOptions::Persons::kAuto;
}

}  // namespace fvv

#endif  // FVV_TOOLS_FVV_PERSONS_OPTION_H_
