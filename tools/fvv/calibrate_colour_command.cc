#include "tools/fvv/calibrate_colour_command.h"

#include <algorithm>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "encoder/body/kinematics.h"
#include "encoder/capture/capture.h"
#include "encoder/capture/colour_gain.h"
#include "encoder/shape/colour_calibration.h"
#include "encoder/track/track_capture.h"
#include "tools/fvv/camera_names.h"
#include "tools/fvv/frame_range.h"

namespace fvv {
namespace {

struct CalibrateColourArgs {
  std::string capture, frames = "0:59", models;
  std::vector<std::string> cameras;  // calibrated among themselves; empty: all
  bool write = false, quiet = false;
};

int Fail(const Status& s) {
  std::fprintf(stderr, "fvv: %s\n", s.ToString().c_str());
  return 1;
}

int RunCalibrateColour(const CalibrateColourArgs& a) {
  StatusOr<Capture> cap = LoadCapture(a.capture);
  if (!cap.ok()) return Fail(cap.status());
  uint32_t first = 0, last = 59;
  if (Status s = ParseFrameRange(a.frames, &first, &last); !s.ok()) return Fail(s);
  if (first >= cap->frame_count) {
    return Fail(InvalidArgument("--frames " + a.frames + ": the capture has " +
                                std::to_string(cap->frame_count) + " frames"));
  }
  last = std::min(last, cap->frame_count - 1);
  // The chosen cameras alone: the others keep their gains.
  StatusOr<std::vector<size_t>> picked = ChooseCameras(*cap, a.cameras);
  if (!picked.ok()) return Fail(picked.status());
  const std::vector<size_t>& chosen = *picked;
  if (chosen.size() < 2)
    return Fail(InvalidArgument("colour calibration needs two cameras or more"));
  Capture sub = *cap;
  sub.cameras.clear();
  std::vector<Camera> cameras;
  for (size_t c : chosen) {
    sub.cameras.push_back(cap->cameras[c]);
    cameras.push_back(cap->cameras[c].calibration);
  }

  ColourCalibration calibration(cameras);
  std::optional<BodyModel> model;
  TrackCaptureOptions to;
  to.first = first;
  to.last = last;
  to.person_models = a.models;
  if (!a.quiet) {
    to.progress = [](const std::string& line) {
      std::fprintf(stderr, "calibrate-colour: %s\n", line.c_str());
    };
  }
  to.on_frame = [&](uint32_t, const FrameFit& fit, const Tracker& tracker,
                    const std::vector<Image>& images,
                    const std::vector<Image>& silhouettes) -> Status {
    if (!model) model = tracker.Model();
    std::vector<Eigen::Vector3f> normals;
    const std::vector<Eigen::Vector3f> positions =
        SkinPositions(model->mesh, SkinningMatrices(model->skeleton, fit.dofs), &normals);
    return calibration.AddFrame(model->mesh.triangles, positions, normals, images, silhouettes);
  };
  StatusOr<TrackCaptureResult> tracked = TrackCapture(sub, to);
  if (!tracked.ok()) return Fail(tracked.status());
  StatusOr<ColourCalibrationResult> r = calibration.Solve();
  if (!r.ok()) return Fail(r.status());

  std::printf(
      "colour gains of %zu cameras from the actor's surface in frames %u..%u (the fit's mean IoU "
      "%.3f):\n",
      cameras.size(), first, last, tracked->mean_iou);
  std::printf("  %-10s %7s %7s %7s %12s\n", "camera", "R", "G", "B", "shared");
  for (size_t c = 0; c < cameras.size(); ++c) {
    if (!r->calibrated[c]) {
      std::printf("  %-10s shares too little of the surface with the others: gain left as it is\n",
                  cameras[c].name.c_str());
      continue;
    }
    std::printf("  %-10s %7.3f %7.3f %7.3f %12llu\n", cameras[c].name.c_str(), r->gains[c][0],
                r->gains[c][1], r->gains[c][2], static_cast<unsigned long long>(r->points[c]));
  }
  std::printf(
      "the cameras' colours at a surface point they share differ by %.1f %% (median), %.1f %% "
      "with these gains\n",
      100 * r->difference_before, 100 * r->difference_after);
  for (size_t c = 0; c < cameras.size(); ++c) {
    for (double g : r->gains[c]) {
      if (!(g >= kMinColourGain && g <= kMaxColourGain)) {
        return Fail(InvalidArgument(
            "calibrate-colour: camera \"" + cameras[c].name + "\" would need a gain of " +
            std::to_string(g) +
            ": more than two stops apart from the others; check its footage (a camera "
            "looking elsewhere, a wrong file); capture.json is unchanged"));
      }
    }
  }
  if (!a.write) {
    std::printf("(--write stores them in capture.json as each camera's colour_gain)\n");
    return 0;
  }
  Capture out = *cap;
  for (size_t i = 0; i < chosen.size(); ++i) {
    if (r->calibrated[i]) out.cameras[chosen[i]].colour_gain = r->gains[i];
  }
  if (Status s = SaveCapture(out); !s.ok()) return Fail(s);
  std::printf("wrote %s/capture.json with the cameras' colour gains\n", out.directory.c_str());
  return 0;
}

}  // namespace

void AddCalibrateColourCommand(CLI::App* capture, int* exit_code) {
  auto args = std::make_shared<CalibrateColourArgs>();
  CLI::App* cc = capture->add_subcommand(
      "calibrate-colour",
      "Each camera's colour gain (R, G, B) from the actor's surface as the cameras see it: the "
      "actor is tracked over a span of frames, and at every point two cameras see well their "
      "colours' ratio is measured; --write stores the gains, which the encoder's textures and "
      "Renderer I then read the cameras through (docs/capture-format.md)");
  cc->add_option("capture", args->capture, "Capture directory or capture.json")->required();
  cc->add_option("--frames", args->frames,
                 "Frames A:B tracked (the actor in view, turning so that every camera sees him)")
      ->capture_default_str();
  cc->add_option("--cameras", args->cameras,
                 "Calibrate these cameras among themselves (names, comma-separated); the others "
                 "keep their gains (default: all)")
      ->delimiter(',');
  cc->add_flag("--write", args->write, "Write the gains into capture.json");
  cc->add_flag("-q,--quiet", args->quiet, "No per-frame progress");
  cc->add_option("--models", args->models,
                 "Directory of the person models (default: $FVV_MODEL_DIR or ~/.cache/fvv/models)");
  cc->callback([args, exit_code] { *exit_code = RunCalibrateColour(*args); });
}

}  // namespace fvv
