#include "encoder/track/camera_sync.h"

#include <algorithm>
#include <map>

#include "encoder/body/generic_body.h"
#include "encoder/capture/calibration.h"
#include "encoder/track/capture_frames.h"
#include "encoder/track/features.h"

namespace fvv {

std::vector<Eigen::Vector2d> KeypointResiduals(
    const std::vector<Camera>& cameras, uint32_t k,
    const std::vector<std::vector<JointSighting>>& sightings, double tolerance_px) {
  std::map<std::string, std::map<uint32_t, Eigen::Vector2d>> points;
  for (uint32_t c = 0; c < cameras.size(); ++c) {
    if (c == k) continue;
    for (const JointSighting& s : sightings[c]) {
      if (s.confidence >= 0.5) points[GenericJointName(s.joint)][c] = s.pixel;
    }
  }
  const auto world = TriangulateFeatures(points, cameras, tolerance_px);
  std::vector<Eigen::Vector2d> out;
  for (const JointSighting& s : sightings[k]) {
    auto it = world.find(GenericJointName(s.joint));
    Eigen::Vector2d p;
    if (s.confidence < 0.5 || it == world.end() ||
        !ProjectPoint(cameras[k], it->second.position, &p)) {
      continue;
    }
    out.push_back(s.pixel - p);
  }
  return out;
}

double KeypointAgreement(const std::vector<Camera>& cameras, uint32_t k,
                         const std::vector<std::vector<JointSighting>>& sightings,
                         double tolerance_px) {
  const std::vector<Eigen::Vector2d> r = KeypointResiduals(cameras, k, sightings, tolerance_px);
  double sum = 0;
  for (const Eigen::Vector2d& v : r) sum += v.norm();
  return r.empty() ? -1 : sum / double(r.size());
}

namespace {

// A confident sighting as a ray: the camera centre and the unit direction.
struct Ray {
  int joint = -1;
  Eigen::Vector3d origin, direction;
  Eigen::Vector2d pixel;
};

// How far apart two cameras' rays to one joint pass, in pixels: each ray's
// point nearest the other, projected into the other camera, against that
// camera's sighting (both ways, averaged). -1 when the rays are parallel.
double RayGap(const Camera& ca, const Ray& a, const Camera& cb, const Ray& b) {
  const Eigen::Vector3d w = a.origin - b.origin;
  const double d = a.direction.dot(b.direction), e = a.direction.dot(w), f = b.direction.dot(w),
               denom = 1 - d * d;
  if (denom < 1e-9) return -1;
  const double s = (d * f - e) / denom, u = (f - d * e) / denom;
  if (s <= 0 || u <= 0) return -1;  // behind a camera
  Eigen::Vector2d pa, pb;
  if (!ProjectPoint(cb, a.origin + s * a.direction, &pb) ||
      !ProjectPoint(ca, b.origin + u * b.direction, &pa)) {
    return -1;
  }
  return 0.5 * ((pb - b.pixel).norm() + (pa - a.pixel).norm());
}

}  // namespace

StatusOr<FrameOffsets> EstimateFrameOffsets(const Capture& capture, PersonObserver* observer,
                                            const FrameOffsetOptions& o) {
  if (capture.cameras.size() < 3) {
    return InvalidArgument("sync: needs 3 cameras or more (2 always agree)");
  }
  if (o.max_offset < 1 || o.max_offset > 1000)
    return InvalidArgument("sync: the largest offset must be 1..1000 frames");
  const int m = o.max_offset;
  const uint32_t last = std::min(o.last, capture.frame_count - 1);
  if (o.first > last || last - o.first + 1 < uint32_t(2 * m + 2)) {
    return InvalidArgument("sync: frames " + std::to_string(o.first) + ".." + std::to_string(last) +
                           " are too few for offsets up to " + std::to_string(m) +
                           " (give at least " + std::to_string(2 * m + 2) +
                           " frames of the capture)");
  }
  // Sightings of every camera over the span.
  StatusOr<CaptureSightings> read =
      ReadSightings(capture, observer, o.first, last, [&](const std::string& line) {
        if (o.progress) o.progress("sync: " + line);
      });
  if (!read.ok()) return read.status();
  std::vector<Camera> cameras;
  for (const CaptureCamera& c : capture.cameras) cameras.push_back(c.calibration);
  return EstimateFrameOffsets(cameras, *read, o);
}

StatusOr<FrameOffsets> EstimateFrameOffsets(const std::vector<Camera>& cameras,
                                            const CaptureSightings& seen,
                                            const FrameOffsetOptions& o) {
  const uint32_t n = uint32_t(cameras.size());
  if (n < 3) return InvalidArgument("sync: needs 3 cameras or more (2 always agree)");
  if (o.max_offset < 1 || o.max_offset > 1000)
    return InvalidArgument("sync: the largest offset must be 1..1000 frames");
  const int m = o.max_offset;
  if (seen.size() < size_t(2 * m + 2)) {
    return InvalidArgument("sync: " + std::to_string(seen.size()) +
                           " frames are too few for offsets up to " + std::to_string(m) +
                           " (give at least " + std::to_string(2 * m + 2) + ")");
  }
  for (const auto& frame : seen) {
    if (frame.size() != n) return InvalidArgument("sync: sightings of another number of cameras");
  }
  // Frame i of camera c is compared at base frame i - m - offset[c], so the
  // base frames run over the middle.
  const int total = int(seen.size()), span = total - 2 * m;
  // Per camera pair and shift (camera b's frames later than a's by d, |d| up
  // to 2m): the median over frames of the joints' mean ray gap. Pairs depend
  // on the difference of their offsets alone, so the search over offsets is
  // cheap: exhaustive for few cameras.
  std::vector<std::vector<std::vector<Ray>>> rays(static_cast<size_t>(total));
  for (auto& frame : rays) frame.resize(n);
  for (int i = 0; i < total; ++i) {
    for (uint32_t c = 0; c < n; ++c) {
      for (const JointSighting& s : seen[size_t(i)][c]) {
        if (s.confidence < 0.5) continue;
        Ray r;
        r.joint = s.joint;
        r.origin = CameraCentre(cameras[c]);
        r.direction = (UnprojectPixel(cameras[c], s.pixel, 1.0) - r.origin).normalized();
        r.pixel = s.pixel;
        rays[size_t(i)][c].push_back(r);
      }
    }
  }
  const int shifts = 4 * m + 1;
  constexpr double kUnknown = -1;
  std::vector<double> pair_cost(size_t(n) * n * shifts, kUnknown);
  auto cost = [&](uint32_t a, uint32_t b, int d) -> double& {
    return pair_cost[(size_t(a) * n + b) * shifts + size_t(d + 2 * m)];
  };
  for (uint32_t a = 0; a < n; ++a) {
    for (uint32_t b = a + 1; b < n; ++b) {
      for (int d = -2 * m; d <= 2 * m; ++d) {
        std::vector<double> per_frame;
        for (int i = std::max(0, -d); i < total && i + d < total; ++i) {
          double sum = 0;
          int count = 0;
          for (const Ray& ra : rays[size_t(i)][a]) {
            for (const Ray& rb : rays[size_t(i + d)][b]) {
              if (ra.joint != rb.joint) continue;
              const double g = RayGap(cameras[a], ra, cameras[b], rb);
              if (g >= 0) sum += g, ++count;
            }
          }
          if (count >= 3) per_frame.push_back(sum / count);
        }
        if (int(per_frame.size()) < span / 2) continue;
        std::nth_element(per_frame.begin(), per_frame.begin() + per_frame.size() / 2,
                         per_frame.end());
        cost(a, b, d) = per_frame[per_frame.size() / 2];
      }
    }
  }
  auto objective = [&](const std::vector<int>& offsets) {
    double sum = 0;
    for (uint32_t a = 0; a < n; ++a) {
      for (uint32_t b = a + 1; b < n; ++b) {
        const double c = cost(a, b, offsets[b] - offsets[a]);
        if (c != kUnknown) sum += c;
      }
    }
    return sum;
  };
  // What the report shows: per camera, the median over the frames of its
  // keypoints' distance from the others' triangulated.
  auto agreement = [&](const std::vector<int>& offsets, std::vector<double>* per_camera) {
    per_camera->assign(n, -1);
    for (uint32_t k = 0; k < n; ++k) {
      std::vector<double> values;
      for (int i = 0; i < span; ++i) {
        std::vector<std::vector<JointSighting>> at(n);
        for (uint32_t c = 0; c < n; ++c) at[c] = seen[size_t(i + m + offsets[c])][c];
        const double v = KeypointAgreement(cameras, k, at, o.tolerance_px);
        if (v >= 0) values.push_back(v);
      }
      if (values.empty()) continue;
      std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
      (*per_camera)[k] = values[values.size() / 2];
    }
  };
  FrameOffsets r;
  r.frames = uint32_t(span);
  std::vector<int> offsets(n, 0);
  agreement(offsets, &r.before_px);
  double best = objective(offsets);
  double combos = 1;
  for (uint32_t c = 1; c < n; ++c) combos *= 2 * m + 1;
  if (combos <= 2e6) {
    // Every combination, camera 0 held at 0.
    std::vector<int> trial(n, -m);
    trial[0] = 0;
    while (true) {
      const double v = objective(trial);
      if (v < best - 1e-9) best = v, offsets = trial;
      uint32_t c = 1;
      while (c < n && ++trial[c] > m) trial[c++] = -m;
      if (c == n) break;
    }
  } else {
    // Coordinate descent, one camera at a time and two together.
    for (int round = 0; round < 16; ++round) {
      bool moved = false;
      for (uint32_t k = 1; k < n; ++k) {
        for (uint32_t l = k; l < n; ++l) {
          for (int d = -m; d <= m; ++d) {
            std::vector<int> trial = offsets;
            trial[k] = std::clamp(trial[k] + d, -m, m);
            if (l != k) trial[l] = std::clamp(trial[l] + d, -m, m);
            if (trial == offsets) continue;
            const double v = objective(trial);
            if (v < best - 1e-9) best = v, offsets = trial, moved = true;
          }
        }
      }
      if (!moved) break;
    }
  }
  agreement(offsets, &r.after_px);
  const int low = *std::min_element(offsets.begin(), offsets.end());
  for (int& v : offsets) v -= low;
  r.offsets = offsets;
  return r;
}

bool CamerasOutOfStep(const FrameOffsets& r) {
  if (r.offsets.empty() || r.frames < kMinStepCheckFrames) return false;
  const auto [low, high] = std::minmax_element(r.offsets.begin(), r.offsets.end());
  if (*high - *low < 2) return false;
  double before = 0, after = 0;
  int counted = 0;
  for (size_t c = 0; c < r.before_px.size() && c < r.after_px.size(); ++c) {
    if (r.before_px[c] < 0 || r.after_px[c] < 0) continue;
    before += r.before_px[c], after += r.after_px[c], ++counted;
  }
  return counted > 0 && after < 0.95 * before;
}

}  // namespace fvv
