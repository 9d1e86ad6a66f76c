#include "encoder/track/sighting_sides.h"

#include <algorithm>

#include "encoder/body/generic_body.h"
#include "encoder/track/camera_sync.h"

namespace fvv {
namespace {

bool IsArm(int joint) {
  return joint == kLeftShoulder || joint == kLeftElbow || joint == kLeftWrist ||
         joint == kRightShoulder || joint == kRightElbow || joint == kRightWrist;
}

bool IsLeg(int joint) {
  return joint == kLeftHip || joint == kLeftKnee || joint == kLeftAnkle || joint == kRightHip ||
         joint == kRightKnee || joint == kRightAnkle;
}

void Exchange(SideExchange::Limbs limbs, std::vector<JointSighting>* seen) {
  for (JointSighting& s : *seen) {
    const bool take = limbs == SideExchange::Limbs::kBody ||
                      (limbs == SideExchange::Limbs::kArms && IsArm(s.joint)) ||
                      (limbs == SideExchange::Limbs::kLegs && IsLeg(s.joint));
    if (take) s.joint = MirrorJoint(s.joint);
  }
}

// The other cameras' triangulation may leave out a view that disagrees by
// more than this share of camera k's longer side (20 pixels at 1920).
double Tolerance(const Camera& camera) {
  return std::max(5.0, 0.0104 * double(std::max(camera.width, camera.height)));
}

}  // namespace

int MirrorJoint(int joint) {
  switch (joint) {
    case kLeftShoulder:
      return kRightShoulder;
    case kLeftElbow:
      return kRightElbow;
    case kLeftWrist:
      return kRightWrist;
    case kLeftHip:
      return kRightHip;
    case kLeftKnee:
      return kRightKnee;
    case kLeftAnkle:
      return kRightAnkle;
    case kRightShoulder:
      return kLeftShoulder;
    case kRightElbow:
      return kLeftElbow;
    case kRightWrist:
      return kLeftWrist;
    case kRightHip:
      return kLeftHip;
    case kRightKnee:
      return kLeftKnee;
    case kRightAnkle:
      return kLeftAnkle;
    default:
      return joint;
  }
}

std::vector<SideExchange> ExchangeMislabelledSides(
    const std::vector<Camera>& cameras, std::vector<std::vector<JointSighting>>* sightings) {
  std::vector<SideExchange> done;
  const uint32_t n = uint32_t(std::min(cameras.size(), sightings->size()));
  if (n < 3) return done;
  std::vector<bool> changed(n, false);
  constexpr SideExchange::Limbs kWays[] = {SideExchange::Limbs::kBody, SideExchange::Limbs::kArms,
                                           SideExchange::Limbs::kLegs};
  for (uint32_t round = 0; round < n; ++round) {
    SideExchange best;
    double best_ratio = 0;
    for (uint32_t c = 0; c < n; ++c) {
      if (changed[c] || (*sightings)[c].empty()) continue;
      const double tolerance = Tolerance(cameras[c]);
      const double before = KeypointAgreement(cameras, c, *sightings, tolerance);
      if (before <= 0) continue;
      const std::vector<JointSighting> own = (*sightings)[c];
      for (SideExchange::Limbs way : kWays) {
        Exchange(way, &(*sightings)[c]);
        const double after = KeypointAgreement(cameras, c, *sightings, tolerance);
        (*sightings)[c] = own;
        if (after <= 0) continue;
        const double ratio = before / std::max(after, 1e-9);
        if (ratio > best_ratio) best_ratio = ratio, best = {c, way, before, after};
      }
    }
    // Twice as near: a camera that merely disagrees a little (calibration,
    // a joint placed loosely) gains far less from an exchange; one that
    // named the sides the other way gains several times over.
    if (best_ratio < 2) break;
    Exchange(best.limbs, &(*sightings)[best.camera]);
    changed[best.camera] = true;
    done.push_back(best);
  }
  return done;
}

}  // namespace fvv
