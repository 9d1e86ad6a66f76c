#include "encoder/track/sighting_sides.h"

#include <algorithm>

#include "encoder/body/generic_body.h"
#include "encoder/track/camera_sync.h"

namespace fvv {
namespace {

bool IsLeg(int joint) {
  return joint == kLeftHip || joint == kLeftKnee || joint == kLeftAnkle || joint == kRightHip ||
         joint == kRightKnee || joint == kRightAnkle;
}

void Exchange(SideExchange::Limbs limbs, std::vector<JointSighting>* seen) {
  for (JointSighting& s : *seen) {
    const bool take = limbs == SideExchange::Limbs::kBody ||
                      (limbs == SideExchange::Limbs::kLegs) == IsLeg(s.joint);
    if (take) s.joint = MirrorJoint(s.joint);
  }
}

// The other cameras' triangulation may leave out a view that disagrees by
// more than this share of the camera's longer side (20 pixels at 1920).
double Tolerance(const Camera& camera) {
  return std::max(5.0, 0.0104 * double(std::max(camera.width, camera.height)));
}

// Over the cameras that saw the person, their sightings' distance from the
// others' triangulated into them: the mean and the largest; -1 where none
// can be scored.
struct Agreement {
  double mean = -1, worst = -1;
  double median = -1;
  std::vector<double> each;  // per camera of `seeing`, -1 where it cannot be scored
};

Agreement CamerasAgreement(const std::vector<Camera>& cameras, const std::vector<uint32_t>& seeing,
                           const std::vector<std::vector<JointSighting>>& sightings) {
  Agreement out;
  double sum = 0;
  std::vector<double> each;
  for (uint32_t c : seeing) {
    const double a = KeypointAgreement(cameras, c, sightings, Tolerance(cameras[c]));
    out.each.push_back(a);
    if (a < 0) continue;
    sum += a;
    each.push_back(a);
    out.worst = std::max(out.worst, a);
  }
  if (each.empty()) return out;
  out.mean = sum / double(each.size());
  std::nth_element(each.begin(), each.begin() + each.size() / 2, each.end());
  out.median = each[each.size() / 2];
  return out;
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

SideExchange ExchangeMislabelledSides(const std::vector<Camera>& cameras,
                                      std::vector<std::vector<JointSighting>>* sightings,
                                      size_t every_camera_tried_up_to) {
  SideExchange done;
  std::vector<uint32_t> seeing;
  for (uint32_t c = 0; c < std::min(cameras.size(), sightings->size()); ++c) {
    if (!(*sightings)[c].empty()) seeing.push_back(c);
  }
  if (seeing.size() < 3) return done;
  Agreement now = CamerasAgreement(cameras, seeing, *sightings);
  done.before_px = done.after_px = now.mean;
  if (now.mean <= 0) return done;
  constexpr SideExchange::Limbs kLimbs[] = {SideExchange::Limbs::kBody, SideExchange::Limbs::kArms,
                                            SideExchange::Limbs::kLegs};
  // One camera at a time, fewer than half of those that see the person.
  while (2 * (done.exchanges.size() + 1) < seeing.size()) {
    // Trying every camera each way, every camera scored again, is cubic in
    // cameras: 23 s a frame for a 32-camera dome. In a large rig a camera
    // named the other way round stands out from the rest, several times
    // their distance: only such cameras are tried there, and where none
    // stands out, none is.
    const bool many = seeing.size() > every_camera_tried_up_to;
    if (many && now.worst < 2 * now.median) break;
    // Every camera not yet exchanged, each way; the best, and the best of
    // the other cameras.
    struct Trial {
      uint32_t camera;
      SideExchange::Limbs limbs;
      double score;  // the mean agreement with the exchange
      double worst;
    };
    std::vector<Trial> trials;
    for (size_t i = 0; i < seeing.size(); ++i) {
      const uint32_t c = seeing[i];
      if (many && now.each[i] < 2 * now.median) continue;
      if (std::any_of(done.exchanges.begin(), done.exchanges.end(),
                      [c](const SideExchange::One& e) { return e.camera == c; })) {
        continue;
      }
      const std::vector<JointSighting> own = (*sightings)[c];
      for (SideExchange::Limbs limbs : kLimbs) {
        Exchange(limbs, &(*sightings)[c]);
        const Agreement a = CamerasAgreement(cameras, seeing, *sightings);
        (*sightings)[c] = own;
        if (a.mean >= 0) trials.push_back({c, limbs, a.mean, a.worst});
      }
    }
    if (trials.empty()) break;
    const Trial best =
        *std::min_element(trials.begin(), trials.end(),
                          [](const Trial& a, const Trial& b) { return a.score < b.score; });
    const Trial* rival = nullptr;
    for (const Trial& t : trials) {
      if (t.camera != best.camera && (!rival || t.score < rival->score)) rival = &t;
    }
    // Twice as near: a labelling that is right gains little from any
    // exchange (side on, left and right lie close in the image), one named
    // the other way round gains several times over.
    if (2 * best.score > now.mean) break;
    // The last exchange there is room for must leave no camera disagreeing:
    // half of the cameras against the other half halves the mean with
    // either half exchanged, and leaves the other.
    const bool last = 2 * (done.exchanges.size() + 2) >= seeing.size();
    if (last && 2 * best.worst > now.worst) break;
    if (rival && 1.5 * best.score > rival->score) {
      // (Without room for both, the two may be a half of the cameras.)
      if (last) break;
      // Another camera's exchange does nearly as well. Two cameras facing
      // each other, neither sure, contend for one disagreement: with both
      // made it is no better, and nothing tells which is wrong. Two cameras
      // each wrong in their own way: both together halve it again.
      const std::vector<JointSighting> own = (*sightings)[best.camera],
                                       other = (*sightings)[rival->camera];
      Exchange(best.limbs, &(*sightings)[best.camera]);
      Exchange(rival->limbs, &(*sightings)[rival->camera]);
      const double both = CamerasAgreement(cameras, seeing, *sightings).mean;
      (*sightings)[best.camera] = own;
      (*sightings)[rival->camera] = other;
      if (both < 0 || 2 * both > best.score) break;
    }
    Exchange(best.limbs, &(*sightings)[best.camera]);
    done.exchanges.push_back({best.camera, best.limbs});
    now = CamerasAgreement(cameras, seeing, *sightings);
  }
  done.after_px = now.mean;
  return done;
}

}  // namespace fvv
