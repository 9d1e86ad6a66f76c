// Which reading of a calibration file the footage agrees with. An import
// chooses conventions a file does not spell out (where pixel (0, 0)'s centre
// lies, what unit the distortion terms are in, how a recording narrower than
// the calibration's window was cut from it), and each wrong choice shows as an
// image shift or a bow in the cameras. Each convention is tried on the whole
// rig, and each camera is judged while it is held out: the person network's
// keypoints in the other cameras are triangulated and projected into it, and
// its own keypoints are compared with them over many frames. A convention that
// is right leaves each camera's residual small and without a constant part; a
// constant residual that no convention removes is the calibration's (a camera
// turned or moved since it was calibrated), not the import's.
//
//   build/bench/calib_conventions_bench CAPTURE [--frames A:B] [--calib FILE]
//                                       [--models DIR] [--json OUT]
//
// CAPTURE: an imported capture (fvv capture import-calib, then fvv capture
// sync --write). --calib: the calibration file it was imported from, so that a
// camera recording fewer columns or rows than its calibrated window is known
// (the crop conventions are tried on those cameras only).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "encoder/capture/calibration_import.h"
#include "encoder/capture/capture.h"
#include "encoder/track/camera_sync.h"
#include "encoder/track/capture_frames.h"
#include "encoder/track/person_observer.h"

namespace fvv {
namespace {

struct Args {
  std::string capture, calib, models, json;
  uint32_t first = 0, last = 97;
};

// A way of reading the rig: the cameras as imported, changed by `apply`.
struct Convention {
  std::string name, what;
  std::function<void(std::vector<Camera>*)> apply;
};

struct CameraResidual {
  Eigen::Vector2d median = Eigen::Vector2d::Zero();  // the constant part (px)
  double median_distance = -1;                       // of the keypoints from the prediction
  double spread = -1;  // median distance once the constant part is taken away
  uint32_t sightings = 0;
};

bool SameIntrinsics(const std::vector<Camera>& a, const std::vector<Camera>& b) {
  for (size_t i = 0; i < a.size(); ++i) {
    if (a[i].fx != b[i].fx || a[i].fy != b[i].fy || a[i].cx != b[i].cx || a[i].cy != b[i].cy ||
        a[i].distortion != b[i].distortion) {
      return false;
    }
  }
  return true;
}

double Median(std::vector<double> v) {
  if (v.empty()) return -1;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// Camera k's keypoints against the other cameras' triangulated and projected
// into it, over every frame.
CameraResidual HeldOutResidual(const std::vector<Camera>& cameras, uint32_t k,
                               const CaptureSightings& seen) {
  std::vector<Eigen::Vector2d> residuals;
  for (const auto& frame : seen) {
    const std::vector<Eigen::Vector2d> r = KeypointResiduals(cameras, k, frame, 20.0);
    residuals.insert(residuals.end(), r.begin(), r.end());
  }
  CameraResidual r;
  r.sightings = uint32_t(residuals.size());
  if (residuals.empty()) return r;
  std::vector<double> xs, ys, d;
  for (const auto& v : residuals) xs.push_back(v.x()), ys.push_back(v.y()), d.push_back(v.norm());
  r.median = {Median(xs), Median(ys)};
  r.median_distance = Median(d);
  d.clear();
  for (const auto& v : residuals) d.push_back((v - r.median).norm());
  r.spread = Median(d);
  return r;
}

int Run(const Args& a) {
  StatusOr<Capture> cap = LoadCapture(a.capture);
  if (!cap.ok()) {
    std::fprintf(stderr, "calib_conventions_bench: %s\n", cap.status().ToString().c_str());
    return 1;
  }
  const uint32_t n = uint32_t(cap->cameras.size());
  if (n < 3) {
    std::fprintf(stderr, "calib_conventions_bench: needs 3 cameras or more\n");
    return 1;
  }
  // The calibrated window of each camera, where the file is given.
  std::vector<uint32_t> window_w(n, 0), window_h(n, 0);
  if (!a.calib.empty()) {
    StatusOr<ImportedCalibration> imported = ImportCalibrationFiles({a.calib}, 1.0);
    if (!imported.ok()) {
      std::fprintf(stderr, "calib_conventions_bench: %s\n", imported.status().ToString().c_str());
      return 1;
    }
    for (uint32_t c = 0; c < n; ++c) {
      for (const Camera& k : imported->cameras) {
        if (k.name != cap->cameras[c].calibration.name) continue;
        window_w[c] = k.width;
        window_h[c] = k.height;
      }
    }
  }
  StatusOr<std::unique_ptr<PersonObserver>> observer =
      PersonObserver::Load(a.models.empty() ? DefaultModelDirectory() : a.models);
  if (!observer.ok()) {
    std::fprintf(stderr, "calib_conventions_bench: %s\n", observer.status().ToString().c_str());
    return 1;
  }
  const uint32_t last = std::min(a.last, cap->frame_count - 1);
  std::printf("keypoints of frames %u..%u in %u cameras ...\n", a.first, last, n);
  StatusOr<CaptureSightings> seen =
      ReadSightings(*cap, observer->get(), a.first, last,
                    [](const std::string& line) { std::printf("  %s\n", line.c_str()); });
  if (!seen.ok()) {
    std::fprintf(stderr, "calib_conventions_bench: %s\n", seen.status().ToString().c_str());
    return 1;
  }
  // The conventions an import of a studio file chooses. Each is applied to
  // every camera it concerns, all at once.
  auto each = [](std::function<void(Camera*)> f) {
    return [f](std::vector<Camera>* cams) {
      for (Camera& k : *cams) f(&k);
    };
  };
  auto narrower = [&](std::function<void(Camera*, double, double)> f) {
    return [&, f](std::vector<Camera>* cams) {
      for (uint32_t c = 0; c < n; ++c) {
        const Camera& k = (*cams)[c];
        if (window_w[c] == 0) continue;
        const double dw = double(window_w[c]) - k.width, dh = double(window_h[c]) - k.height;
        if (dw != 0 || dh != 0) f(&(*cams)[c], dw, dh);
      }
    };
  };
  std::vector<Convention> conventions = {
      {"as-imported", "fvv's reading (docs/capture-format.md)", [](std::vector<Camera>*) {}},
      {"distortion/64", "distortion terms divided by 64, as Pose2Sim's converter does",
       each([](Camera* k) {
         for (double& d : k->distortion) d /= 64;
       })},
      {"no-distortion", "lens distortion left out (what the terms move, either way)",
       each([](Camera* k) {
         for (double& d : k->distortion) d = 0;
       })},
      {"origin+0.5", "pixel (0, 0)'s centre at (0.5, 0.5) in the file's coordinates",
       each([](Camera* k) { k->cx -= 0.5, k->cy -= 0.5; })},
      {"origin-0.5", "the other way: principal point half a pixel further",
       each([](Camera* k) { k->cx += 0.5, k->cy += 0.5; })},
      {"swap-uv", "centerPointU/V read as rows/columns (a rotated sensor)", each([](Camera* k) {
         // The principal point mirrored through the image centre on both
         // axes: what a 180-degree turned sensor readout gives.
         k->cx = k->width - 1 - k->cx;
         k->cy = k->height - 1 - k->cy;
       })},
      {"crop-centred", "narrower recordings cut from the window's middle",
       narrower([](Camera* k, double dw, double dh) { k->cx -= dw / 2, k->cy -= dh / 2; })},
      {"crop-left-top", "narrower recordings cut from the window's left and top",
       narrower([](Camera* k, double dw, double dh) { k->cx -= dw, k->cy -= dh; })},
      {"scaled", "narrower recordings scaled from the window",
       narrower([](Camera* k, double dw, double dh) {
         const double sx = k->width / (k->width + dw), sy = k->height / (k->height + dh);
         k->fx *= sx, k->cx = (k->cx + 0.5) * sx - 0.5;
         k->fy *= sy, k->cy = (k->cy + 0.5) * sy - 0.5;
       })},
  };
  std::vector<Camera> base;
  for (const CaptureCamera& c : cap->cameras) base.push_back(c.calibration);
  nlohmann::json out = nlohmann::json::array();
  std::printf("\n%-14s", "convention");
  for (uint32_t c = 0; c < n; ++c) {
    std::printf(" | %-30s", (base[c].name + ": dx dy / dist / spread").c_str());
  }
  std::printf(" | mean dist\n");
  for (const Convention& conv : conventions) {
    std::vector<Camera> cams = base;
    conv.apply(&cams);
    if (conv.name != "as-imported" && SameIntrinsics(cams, base)) {
      std::printf("%-14s   (no camera concerned)\n", conv.name.c_str());
      continue;
    }
    std::printf("%-14s", conv.name.c_str());
    double sum = 0;
    int counted = 0;
    nlohmann::json row = {{"convention", conv.name}, {"what", conv.what}};
    for (uint32_t k = 0; k < n; ++k) {
      const CameraResidual r = HeldOutResidual(cams, k, *seen);
      char cell[64];
      std::snprintf(cell, sizeof(cell), "%+6.1f %+6.1f / %5.1f / %5.1f", r.median.x(), r.median.y(),
                    r.median_distance, r.spread);
      std::printf(" | %-30s", cell);
      if (r.median_distance >= 0) sum += r.median_distance, ++counted;
      row["cameras"][base[k].name] = {{"dx", r.median.x()},
                                      {"dy", r.median.y()},
                                      {"median_px", r.median_distance},
                                      {"spread_px", r.spread},
                                      {"sightings", r.sightings}};
    }
    const double mean = counted ? sum / counted : -1;
    row["mean_median_px"] = mean;
    std::printf(" | %5.1f\n", mean);
    out.push_back(row);
  }
  std::printf(
      "\ndx dy: the median of where each camera sees a keypoint minus where the other cameras "
      "put it (px);\ndist: the median distance; spread: the median distance once dx dy are "
      "taken away.\n");
  if (!a.json.empty()) {
    std::ofstream(a.json) << out.dump(2) << "\n";
    std::printf("figures -> %s\n", a.json.c_str());
  }
  return 0;
}

}  // namespace
}  // namespace fvv

int main(int argc, char** argv) {
  fvv::Args a;
  auto usage = [] {
    std::fprintf(stderr,
                 "usage: calib_conventions_bench CAPTURE [--frames A:B] [--calib FILE] "
                 "[--models DIR] [--json OUT]\n");
    return 2;
  };
  for (int i = 1; i < argc; ++i) {
    const std::string s = argv[i];
    if (s == "-h" || s == "--help") return usage(), 0;
    if (i + 1 < argc && (s == "--frames" || s == "--calib" || s == "--models" || s == "--json")) {
      const std::string v = argv[++i];
      if (s == "--frames") {
        if (std::sscanf(v.c_str(), "%u:%u", &a.first, &a.last) != 2 || a.last < a.first) {
          return usage();
        }
      } else {
        (s == "--calib" ? a.calib : s == "--models" ? a.models : a.json) = v;
      }
    } else if (s[0] != '-' && a.capture.empty()) {
      a.capture = s;
    } else {
      return usage();
    }
  }
  if (a.capture.empty()) return usage();
  return fvv::Run(a);
}
