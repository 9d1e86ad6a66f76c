#include "tools/fvv/register_command.h"

#include <chrono>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "encoder/body/body_shape_json.h"
#include "encoder/capture/capture.h"
#include "encoder/encode/pose_file.h"
#include "encoder/io/image_io.h"
#include "encoder/track/feature_registration.h"
#include "encoder/track/features.h"
#include "encoder/track/joint_truth.h"
#include "tools/fvv/frame_range.h"

namespace fvv {
namespace {

struct RegisterArgs {
  std::string capture, features, output, frames, truth;
  bool fixed_shape = false, quiet = false;
};

int Fail(const Status& s) {
  std::fprintf(stderr, "fvv: %s\n", s.ToString().c_str());
  return 1;
}

int RunRegister(const RegisterArgs& a) {
  const auto start = std::chrono::steady_clock::now();
  StatusOr<Capture> cap = LoadCapture(a.capture);
  if (!cap.ok()) return Fail(cap.status());
  std::vector<Camera> cameras;
  for (const CaptureCamera& c : cap->cameras) cameras.push_back(c.calibration);
  StatusOr<FeatureSet> features = LoadFeatures(a.features, cameras, cap->frame_count);
  if (!features.ok()) return Fail(features.status());
  if (features->frames.empty()) return Fail(InvalidArgument(a.features + " has no features"));
  uint32_t first = features->frames.begin()->first, last = features->frames.rbegin()->first;
  if (Status s = ParseFrameRange(a.frames, &first, &last); !s.ok()) return Fail(s);
  if (last >= cap->frame_count) {
    return Fail(InvalidArgument("--frames beyond the capture's " +
                                std::to_string(cap->frame_count) + " frames"));
  }
  // The first frame fits the proportions (unless --fixed-shape); later frames
  // start from the previous pose with the proportions kept.
  BodyShape shape;
  std::vector<double> previous;
  nlohmann::json frames = nlohmann::json::array();
  double rms_sum = 0;
  std::vector<std::vector<double>> poses;
  for (uint32_t f = first; f <= last; ++f) {
    std::map<std::string, Feature3D> points;
    if (features->frames.count(f)) points = TriangulateFeatures(features->frames.at(f), cameras);
    RegistrationOptions o;
    o.fit_shape = previous.empty() && !a.fixed_shape;
    StatusOr<Registration> r = RegisterSkeleton(points, shape, previous, o);
    if (!r.ok()) {
      return Fail(Status(r.status().code(), "frame " + std::to_string(f) + ": " +
                                                r.status().message() + " (" +
                                                std::to_string(points.size()) +
                                                " joints seen by two or more cameras)"));
    }
    if (previous.empty()) shape = r->shape;
    previous = r->dofs;
    poses.push_back(r->dofs);
    rms_sum += r->rms_m;
    frames.push_back({{"frame", f}, {"dofs", r->dofs}, {"joints", r->joints}, {"rms_m", r->rms_m}});
    if (!a.quiet) {
      std::printf("register: frame %u: %d joints, rms %.2f cm (%.2f cm from the %s)\n", f,
                  r->joints, r->rms_m * 100, r->initial_rms_m * 100,
                  f == first ? "analytic initialisation" : "previous frame's pose");
    }
  }
  nlohmann::json out;
  out["generator"] = "fvv capture register";
  out["capture"] = cap->directory;
  out["features"] = a.features;
  out["dof_names"] = GenericDofNames();
  out["body_shape"] = BodyShapeToJson(shape);
  out["frame_rate"] = cap->frame_rate;
  out["frames"] = frames;
  const std::string text = out.dump(1) + "\n";
  if (Status s =
          WriteFileAtomic(a.output, reinterpret_cast<const uint8_t*>(text.data()), text.size());
      !s.ok()) {
    return Fail(s);
  }
  const uint32_t n = last - first + 1;
  std::printf("registered frames %u..%u from %s: mean joint rms %.2f cm, %.3f s per frame -> %s\n",
              first, last, a.features.c_str(), rms_sum / n * 100,
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / n,
              a.output.c_str());
  if (!a.truth.empty()) {
    StatusOr<JointErrors> e = CompareWithTruth(a.truth, MakeGenericSkeleton(shape), poses, first);
    if (!e.ok()) return Fail(e.status());
    std::printf("joint error against %s: mean %.2f cm, max %.2f cm (%s)\n", a.truth.c_str(),
                e->mean * 100, e->max * 100, e->Describe().c_str());
  }
  return 0;
}

}  // namespace

void AddRegisterCommand(CLI::App* capture, int* exit_code) {
  auto a = std::make_shared<RegisterArgs>();
  CLI::App* r = capture->add_subcommand(
      "register",
      "Poses and body proportions from feature points (joint centres marked per camera image): "
      "triangulated, then the generic body fitted to them; writes a poses.json for fvv encode "
      "--poses");
  r->add_option("capture", a->capture, "Capture directory or capture.json")->required();
  r->add_option("--features", a->features,
                "Feature points: {\"features\": [{\"frame\": F, \"camera\": NAME, \"points\": "
                "{\"l_knee\": [x, y], ...}}, ...]} (fvv synth writes truth/features.json)")
      ->required()
      ->check(CLI::ExistingFile);
  r->add_option("-o,--output", a->output, "Poses (JSON)")->required();
  r->add_option("--frames", a->frames, "Frame range A:B (default: the frames with features)");
  r->add_flag("--fixed-shape", a->fixed_shape, "Keep the generic body's proportions");
  r->add_option("--truth", a->truth, "Report joint errors against a synthetic capture's truth");
  r->add_flag("-q,--quiet", a->quiet, "No per-frame lines");
  r->callback([a, exit_code] { *exit_code = RunRegister(*a); });
}

}  // namespace fvv
