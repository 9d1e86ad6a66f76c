#include "tools/synth/procedural_motion.h"

#include <cmath>

#include "encoder/body/generic_body.h"
#include "encoder/body/kinematics.h"

namespace fvv {

std::vector<std::vector<double>> ProceduralWalk(const Skeleton& skeleton, uint32_t frames,
                                                double fps) {
  constexpr double kPi = 3.14159265358979323846;
  const size_t n = skeleton.Dofs().size();
  const double stride_period = 1.1;        // seconds per two steps
  const double radius = 0.7, speed = 0.6;  // metres, metres per second
  std::vector<std::vector<double>> out;
  for (uint32_t f = 0; f < frames; ++f) {
    const double t = f / fps;
    const double ph = 2 * kPi * t / stride_period;
    std::vector<double> v(n, 0.0);
    auto set = [&](int bone, int kind, double value) {
      const int i = DofIndex(skeleton, bone, kind);
      if (i >= 0) v[i] = value;
    };
    // Along a circle, counter-clockwise seen from above, facing along the path.
    const double a = speed * t / radius;
    set(kRoot, 3, radius * std::cos(a) - radius);
    set(kRoot, 5, -radius * std::sin(a));
    set(kRoot, 4, -0.02 + 0.015 * std::cos(2 * ph));  // bob twice per stride
    set(kRoot, 1, a + kPi);                           // yaw: face the direction of travel
    set(kLumbar, 0, 0.06);
    set(kThoracic, 1, -0.12 * std::sin(ph));
    set(kNeck, 0, 0.05);
    set(kHead, 1, 0.35 * std::sin(2 * kPi * t / 4.0));
    for (int side = 0; side < 2; ++side) {
      const double s = side == 0 ? 1 : -1;  // left, right
      const double p = ph + side * kPi;
      const int hip = side == 0 ? kLeftHip : kRightHip, knee = side == 0 ? kLeftKnee : kRightKnee;
      const int ankle = side == 0 ? kLeftAnkle : kRightAnkle;
      const int shoulder = side == 0 ? kLeftShoulder : kRightShoulder;
      const int elbow = side == 0 ? kLeftElbow : kRightElbow;
      set(hip, 0, -0.38 * std::sin(p) - 0.05);
      set(hip, 2, s * 0.04);
      set(knee, 0, 0.55 * std::max(0.0, std::sin(p - 1.2)) + 0.1);
      set(ankle, 0, 0.2 * std::sin(p - 0.4));
      set(shoulder, 2, -s * 1.3);                // arms down from the T-pose
      set(shoulder, 1, s * 0.35 * std::sin(p));  // swing opposite to the leg
      set(shoulder, 0, 0.0);
      set(elbow, 1, -s * (0.3 + 0.15 * std::sin(p + kPi / 2)));
    }
    out.push_back(ClampToLimits(skeleton, v));
  }
  return out;
}

}  // namespace fvv
