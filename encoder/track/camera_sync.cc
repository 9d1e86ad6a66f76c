#include "encoder/track/camera_sync.h"

#include <algorithm>
#include <map>

#include "codec/base/thread_pool.h"
#include "encoder/body/generic_body.h"
#include "encoder/capture/calibration.h"
#include "encoder/track/capture_frames.h"
#include "encoder/track/features.h"

namespace fvv {

double KeypointAgreement(const std::vector<Camera>& cameras, uint32_t k,
                         const std::vector<std::vector<JointSighting>>& sightings,
                         double tolerance_px) {
  std::map<std::string, std::map<uint32_t, Eigen::Vector2d>> points;
  for (uint32_t c = 0; c < cameras.size(); ++c) {
    if (c == k) continue;
    for (const JointSighting& s : sightings[c]) {
      if (s.confidence >= 0.5) points[GenericJointName(s.joint)][c] = s.pixel;
    }
  }
  const auto world = TriangulateFeatures(points, cameras, tolerance_px);
  double sum = 0;
  int n = 0;
  for (const JointSighting& s : sightings[k]) {
    auto it = world.find(GenericJointName(s.joint));
    Eigen::Vector2d p;
    if (s.confidence < 0.5 || it == world.end() ||
        !ProjectPoint(cameras[k], it->second.position, &p)) {
      continue;
    }
    sum += (p - s.pixel).norm();
    ++n;
  }
  return n ? sum / n : -1;
}

StatusOr<FrameOffsets> EstimateFrameOffsets(const Capture& capture, PersonObserver* observer,
                                            const FrameOffsetOptions& o) {
  const uint32_t n = uint32_t(capture.cameras.size());
  if (n < 3) return InvalidArgument("sync: needs 3 cameras or more (2 always agree)");
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
  // Sightings of every camera over the span; frame i of camera c is compared
  // at base frame i - m - offset[c], so the base frames run over the middle.
  ThreadPool pool(2);
  StatusOr<std::unique_ptr<CaptureFrames>> frames =
      CaptureFrames::Open(capture, false, &pool, observer);
  if (!frames.ok()) return frames.status();
  std::vector<std::vector<std::vector<JointSighting>>> seen;  // [frame][camera]
  for (uint32_t f = o.first; f <= last; ++f) {
    std::vector<Image> sils;
    FVV_RETURN_IF_ERROR((*frames)->Read(f, nullptr, &sils));
    seen.push_back((*frames)->sightings());
    if (o.progress && (f - o.first) % 10 == 9) {
      o.progress("sync: keypoints of frame " + std::to_string(f) + " (" +
                 std::to_string(f - o.first + 1) + "/" + std::to_string(last - o.first + 1) + ")");
    }
  }
  std::vector<Camera> cameras;
  for (const CaptureCamera& c : capture.cameras) cameras.push_back(c.calibration);
  const int span = int(seen.size()) - 2 * m;
  // Per camera the median over the frames (a frame where the network took
  // someone else, or lost a limb, does not count for more than one).
  auto agreement = [&](const std::vector<int>& offsets, std::vector<double>* per_camera) {
    double total = 0;
    if (per_camera) per_camera->assign(n, -1);
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
      const double median = values[values.size() / 2];
      total += median;
      if (per_camera) (*per_camera)[k] = median;
    }
    return total;
  };
  FrameOffsets r;
  r.frames = uint32_t(span);
  std::vector<int> offsets(n, 0);
  agreement(offsets, &r.before_px);
  double best = agreement(offsets, nullptr);
  // Coordinate descent, one camera at a time and then two together (moving
  // one camera is moving all the others the other way; two cameras that
  // started late together look in step with each other).
  auto clamp = [&](int v) { return std::clamp(v, -m, m); };
  for (int round = 0; round < 8; ++round) {
    bool moved = false;
    for (uint32_t k = 0; k < n; ++k) {
      for (uint32_t l = k; l < n; ++l) {
        for (int d = -m; d <= m; ++d) {
          if (d == 0) continue;
          std::vector<int> trial = offsets;
          trial[k] = clamp(trial[k] + d);
          if (l != k) trial[l] = clamp(trial[l] + d);
          if (trial == offsets) continue;
          const double v = agreement(trial, nullptr);
          if (v < best - 1e-9) best = v, offsets = trial, moved = true;
        }
      }
    }
    if (!moved) break;
  }
  agreement(offsets, &r.after_px);
  const int low = *std::min_element(offsets.begin(), offsets.end());
  for (int& v : offsets) v -= low;
  r.offsets = offsets;
  return r;
}

}  // namespace fvv
