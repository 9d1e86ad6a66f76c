#include "player/export/bvh_writer.h"

#include <cmath>
#include <cstdio>
#include <glm/gtc/constants.hpp>
#include <glm/mat3x3.hpp>

#include "codec/base/atomic_file.h"

namespace fvv {
namespace {

constexpr double kCentimetres = 100;

const char* AxisName(int axis) { return axis == 0 ? "X" : axis == 1 ? "Y" : "Z"; }

float Unwrap(float angle, float near) {
  const float two_pi = glm::two_pi<float>();
  return angle + two_pi * std::round((near - angle) / two_pi);
}

std::string Number(double v) {
  char s[32];
  std::snprintf(s, sizeof(s), "%.6f", std::abs(v) < 5e-7 ? 0.0 : v);
  return s;
}

void Hierarchy(const ExportedActor& a, int j, int depth, std::string* out) {
  const std::string pad(2 * depth, ' ');
  const ExportedJoint& joint = a.joints[j];
  const std::string name = joint.name.empty() ? "joint" + std::to_string(j) : joint.name;
  *out += pad + (joint.parent < 0 ? "ROOT " : "JOINT ") + name + "\n" + pad + "{\n";
  // A root's place is all in its position channels (tools differ on adding
  // a root's offset to them).
  const glm::vec3 o =
      joint.parent < 0 ? glm::vec3(0.0f) : joint.rest_translation * float(kCentimetres);
  *out += pad + "  OFFSET " + Number(o.x) + " " + Number(o.y) + " " + Number(o.z) + "\n";
  const auto axes = RotationOrderAxes(joint.order);
  *out += pad + (joint.parent < 0 ? "  CHANNELS 6 Xposition Yposition Zposition" : "  CHANNELS 3");
  for (int axis : axes) *out += std::string(" ") + AxisName(axis) + "rotation";
  *out += "\n";
  bool leaf = true;
  for (size_t c = 0; c < a.joints.size(); ++c) {
    if (a.joints[c].parent != j) continue;
    leaf = false;
    Hierarchy(a, int(c), depth + 1, out);
  }
  if (leaf) {
    const glm::vec3 end = glm::length(o) > 0 ? 0.5f * o : glm::vec3(0.0f, 5.0f, 0.0f);
    *out += pad + "  End Site\n" + pad + "  {\n" + pad + "    OFFSET " + Number(end.x) + " " +
            Number(end.y) + " " + Number(end.z) + "\n" + pad + "  }\n";
  }
  *out += pad + "}\n";
}

// Joints in the order the hierarchy lists them (depth first), which is the
// order of the motion lines' channels.
void ListOrder(const ExportedActor& a, int j, std::vector<int>* order) {
  order->push_back(j);
  for (size_t c = 0; c < a.joints.size(); ++c) {
    if (a.joints[c].parent == j) ListOrder(a, int(c), order);
  }
}

}  // namespace

glm::vec3 EulerAngles(const glm::quat& rotation, RotationOrder order, const glm::vec3& previous) {
  const glm::mat3 m = glm::mat3_cast(rotation);
  const auto R = [&m](int row, int col) { return double(m[col][row]); };  // glm is column-major
  const auto axes = RotationOrderAxes(order);
  const int i = axes[0], j = axes[1], k = axes[2];
  // +1 when (i, j, k) is an even permutation of (x, y, z).
  const double s = ((j - i + 3) % 3 == 1) ? 1.0 : -1.0;
  const double sb = std::max(-1.0, std::min(1.0, s * R(i, k)));
  glm::vec3 e(float(std::atan2(-s * R(j, k), R(k, k))), float(std::asin(sb)),
              float(std::atan2(-s * R(i, j), R(i, i))));
  const float pi = glm::pi<float>();
  glm::vec3 other(e.x + pi, pi - e.y, e.z + pi);
  float d0 = 0, d1 = 0;
  for (int a = 0; a < 3; ++a) {
    e[a] = Unwrap(e[a], previous[a]);
    other[a] = Unwrap(other[a], previous[a]);
    d0 += std::abs(e[a] - previous[a]);
    d1 += std::abs(other[a] - previous[a]);
  }
  return d1 < d0 ? other : e;
}

std::string BvhText(const ExportedActor& a) {
  std::string out = "HIERARCHY\n";
  std::vector<int> order;
  for (size_t j = 0; j < a.joints.size(); ++j) {
    if (a.joints[j].parent >= 0) continue;
    Hierarchy(a, int(j), 0, &out);
    ListOrder(a, int(j), &order);
  }
  out += "MOTION\nFrames: " + std::to_string(a.rotation.size()) + "\n";
  out += "Frame Time: " + Number(1.0 / a.fps) + "\n";
  std::vector<glm::vec3> previous(a.joints.size(), glm::vec3(0.0f));
  for (size_t f = 0; f < a.rotation.size(); ++f) {
    std::string line;
    for (int j : order) {
      if (a.joints[j].parent < 0) {
        const glm::vec3 t = a.translation[f][j] * float(kCentimetres);
        line += Number(t.x) + " " + Number(t.y) + " " + Number(t.z) + " ";
      }
      previous[j] = EulerAngles(a.rotation[f][j], a.joints[j].order, previous[j]);
      for (int k = 0; k < 3; ++k) line += Number(glm::degrees(double(previous[j][k]))) + " ";
    }
    line.back() = '\n';
    out += line;
  }
  return out;
}

Status WriteBvh(const ExportedActor& a, const std::string& path) {
  const std::string text = BvhText(a);
  return WriteFileAtomic(path, reinterpret_cast<const uint8_t*>(text.data()), text.size());
}

}  // namespace fvv
