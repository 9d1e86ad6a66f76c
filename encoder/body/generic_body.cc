#include "encoder/body/generic_body.h"

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <vector>

namespace fvv {
namespace {

using Eigen::Vector3d;

constexpr double kPi = 3.14159265358979323846;
constexpr uint8_t kRot3 = kDofRotX | kDofRotY | kDofRotZ;
constexpr uint8_t kTrans3 = kDofTransX | kDofTransY | kDofTransZ;

struct JointSpec {
  const char* name;
  int parent;
  double x, y, z;  // rest position for stature 1 (1.75 m), world
  uint8_t dofs;
  // Limits of rotation about X, Y, Z (radians); only those in `dofs` are used.
  double lo[3], hi[3];
  double blend;  // half-width (metres) of the skinning blend across this joint
};

// Left side at +X. Positive rotation about Z raises the left arm; about X moves
// a leg backwards; about Y (negative) bends the left elbow forwards.
const JointSpec kJoints[kGenericJointCount] = {
    {"root", -1, 0, 0.95, 0, kRot3 | kTrans3, {-kPi, -kPi, -kPi}, {kPi, kPi, kPi}, 0},
    {"lumbar", kRoot, 0, 1.05, 0, kDofRotX | kDofRotZ, {-0.6, 0, -0.6}, {1.2, 0, 0.6}, 0.06},
    {"thoracic", kLumbar, 0, 1.24, 0, kDofRotY, {0, -0.9, 0}, {0, 0.9, 0}, 0.06},
    {"neck", kThoracic, 0, 1.47, 0, kDofRotX, {-0.8, 0, 0}, {1.0, 0, 0}, 0.05},
    {"head", kNeck, 0, 1.57, 0, kDofRotY, {0, -1.4, 0}, {0, 1.4, 0}, 0.05},
    {"l_shoulder", kThoracic, 0.18, 1.43, 0, kRot3, {-1.8, -2.4, -1.9}, {1.8, 1.3, 1.7}, 0.055},
    {"l_elbow", kLeftShoulder, 0.47, 1.43, 0, kDofRotY, {0, -2.7, 0}, {0, 0.1, 0}, 0.04},
    {"l_wrist",
     kLeftElbow,
     0.72,
     1.43,
     0,
     kDofRotY | kDofRotZ,
     {0, -0.6, -1.3},
     {0, 0.6, 1.3},
     0.03},
    {"r_shoulder", kThoracic, -0.18, 1.43, 0, kRot3, {-1.8, -1.3, -1.7}, {1.8, 2.4, 1.9}, 0.055},
    {"r_elbow", kRightShoulder, -0.47, 1.43, 0, kDofRotY, {0, -0.1, 0}, {0, 2.7, 0}, 0.04},
    {"r_wrist",
     kRightElbow,
     -0.72,
     1.43,
     0,
     kDofRotY | kDofRotZ,
     {0, -0.6, -1.3},
     {0, 0.6, 1.3},
     0.03},
    {"l_hip", kRoot, 0.09, 0.9, 0, kRot3, {-2.2, -0.9, -0.6}, {0.8, 0.9, 1.2}, 0.07},
    {"l_knee", kLeftHip, 0.09, 0.48, 0, kDofRotX, {-0.1, 0, 0}, {2.7, 0, 0}, 0.05},
    {"l_ankle",
     kLeftKnee,
     0.09,
     0.085,
     0,
     kDofRotX | kDofRotZ,
     {-0.9, 0, -0.5},
     {0.8, 0, 0.5},
     0.035},
    {"r_hip", kRoot, -0.09, 0.9, 0, kRot3, {-2.2, -0.9, -1.2}, {0.8, 0.9, 0.6}, 0.07},
    {"r_knee", kRightHip, -0.09, 0.48, 0, kDofRotX, {-0.1, 0, 0}, {2.7, 0, 0}, 0.05},
    {"r_ankle",
     kRightKnee,
     -0.09,
     0.085,
     0,
     kDofRotX | kDofRotZ,
     {-0.9, 0, -0.5},
     {0.8, 0, 0.5},
     0.035},
};

struct ProfilePoint {
  double s, half_width, half_depth;  // s in [0, 1] along the axis
};

// A segment: a generalised cylinder along axis A from the bone's joint (plus
// `offset`), between axial positions a0 and a1, with elliptical cross-sections
// (half-width along W, half-depth along A x W) and ellipsoidal end caps whose
// length is cap * the end radius. Right-side segments mirror left ones.
struct SegmentSpec {
  const char* name;
  int bone;
  int mirror_of;  // -1, or the left segment this one mirrors in X
  double axis[3], width_dir[3], offset[3];
  double a0, a1, cap0, cap1;
  std::vector<ProfilePoint> profile;
};

const std::vector<SegmentSpec>& Segments() {
  static const std::vector<SegmentSpec> kSegments = {
      {"pelvis",
       kRoot,
       -1,
       {0, 1, 0},
       {1, 0, 0},
       {0, 0, 0},
       -0.13,
       0.11,
       0.45,
       0.3,
       {{0, 0.15, 0.1}, {0.45, 0.168, 0.112}, {1, 0.145, 0.1}}},
      {"abdomen",
       kLumbar,
       -1,
       {0, 1, 0},
       {1, 0, 0},
       {0, 0, 0},
       -0.05,
       0.23,
       0.3,
       0.3,
       {{0, 0.142, 0.1}, {0.5, 0.135, 0.096}, {1, 0.15, 0.1}}},
      {"chest",
       kThoracic,
       -1,
       {0, 1, 0},
       {1, 0, 0},
       {0, 0, 0},
       -0.03,
       0.22,
       0.3,
       0.45,
       {{0, 0.15, 0.1}, {0.55, 0.165, 0.11}, {0.85, 0.17, 0.1}, {1, 0.125, 0.08}}},
      {"head",
       kNeck,
       -1,
       {0, 1, 0},
       {1, 0, 0},
       {0, 0, 0.01},
       -0.05,
       0.23,
       0.3,
       0.9,
       {{0, 0.055, 0.055},
        {0.3, 0.054, 0.058},
        {0.45, 0.07, 0.082},
        {0.62, 0.082, 0.098},
        {0.85, 0.08, 0.095},
        {1, 0.062, 0.072}}},
      {"l_upper_arm",
       kLeftShoulder,
       -1,
       {1, 0, 0},
       {0, 0, 1},
       {0, 0, 0},
       -0.03,
       0.31,
       0.8,
       0.6,
       {{0, 0.06, 0.055}, {0.3, 0.052, 0.05}, {1, 0.042, 0.04}}},
      {"l_forearm",
       kLeftElbow,
       -1,
       {1, 0, 0},
       {0, 0, 1},
       {0, 0, 0},
       -0.02,
       0.26,
       0.6,
       0.5,
       {{0, 0.042, 0.04}, {0.3, 0.043, 0.038}, {1, 0.031, 0.024}}},
      {"l_hand",
       kLeftWrist,
       -1,
       {1, 0, 0},
       {0, 0, 1},
       {0, 0, 0},
       -0.01,
       0.16,
       0.5,
       0.9,
       {{0, 0.03, 0.018}, {0.4, 0.045, 0.02}, {1, 0.036, 0.013}}},
      {"r_upper_arm", kRightShoulder, 4, {}, {}, {}, 0, 0, 0, 0, {}},
      {"r_forearm", kRightElbow, 5, {}, {}, {}, 0, 0, 0, 0, {}},
      {"r_hand", kRightWrist, 6, {}, {}, {}, 0, 0, 0, 0, {}},
      {"l_thigh",
       kLeftHip,
       -1,
       {0, -1, 0},
       {1, 0, 0},
       {0, 0, 0},
       -0.06,
       0.44,
       0.6,
       0.6,
       {{0, 0.085, 0.09}, {0.3, 0.08, 0.085}, {1, 0.053, 0.055}}},
      {"l_shank",
       kLeftKnee,
       -1,
       {0, -1, 0},
       {1, 0, 0},
       {0, 0, 0},
       -0.02,
       0.39,
       0.6,
       0.6,
       {{0, 0.05, 0.052}, {0.3, 0.055, 0.06}, {1, 0.034, 0.036}}},
      {"l_foot",
       kLeftAnkle,
       -1,
       {0, 0, 1},
       {1, 0, 0},
       {0, -0.04, 0},
       -0.06,
       0.2,
       0.7,
       0.5,
       {{0, 0.035, 0.04}, {0.4, 0.045, 0.04}, {1, 0.04, 0.02}}},
      {"r_thigh", kRightHip, 10, {}, {}, {}, 0, 0, 0, 0, {}},
      {"r_shank", kRightKnee, 11, {}, {}, {}, 0, 0, 0, 0, {}},
      {"r_foot", kRightAnkle, 12, {}, {}, {}, 0, 0, 0, 0, {}},
  };
  return kSegments;
}

// The spec a segment is built from (a right segment: its left twin mirrored).
SegmentSpec Resolved(int segment) {
  const SegmentSpec& own = Segments()[segment];
  if (own.mirror_of < 0) return own;
  SegmentSpec s = Segments()[own.mirror_of];
  s.name = own.name;
  s.bone = own.bone;
  s.mirror_of = own.mirror_of;
  s.axis[0] = -s.axis[0];
  s.width_dir[0] = -s.width_dir[0];
  s.offset[0] = -s.offset[0];
  return s;
}

Vector3d V(const double* v) { return Vector3d(v[0], v[1], v[2]); }

double SmoothStep(double e0, double e1, double x) {
  const double t = std::clamp((x - e0) / (e1 - e0), 0.0, 1.0);
  return t * t * (3 - 2 * t);
}

// Radii at s along the axis: smooth interpolation between profile points.
void ProfileAt(const std::vector<ProfilePoint>& p, double s, double* rw, double* rd) {
  if (s <= p.front().s) {
    *rw = p.front().half_width, *rd = p.front().half_depth;
    return;
  }
  for (size_t i = 1; i < p.size(); ++i) {
    if (s <= p[i].s) {
      const double t = SmoothStep(p[i - 1].s, p[i].s, s);
      *rw = p[i - 1].half_width + t * (p[i].half_width - p[i - 1].half_width);
      *rd = p[i - 1].half_depth + t * (p[i].half_depth - p[i - 1].half_depth);
      return;
    }
  }
  *rw = p.back().half_width, *rd = p.back().half_depth;
}

int SegmentOfBone(int bone) {
  for (int s = 0; s < kGenericSegmentCount; ++s) {
    if (Segments()[s].bone == bone) return s;
  }
  return kSegHead;  // kHead: the upper part of the head segment
}

// The direction a bone's segment runs from its joint (the head joint: up).
Vector3d BoneAxis(int bone) {
  if (bone == kHead) return Vector3d(0, 1, 0);
  return V(Resolved(SegmentOfBone(bone)).axis);
}

// The normal of the plane the skin blends across at a joint: the child
// segment's axis where parent and child segments are (anti)parallel; where they
// meet at a right angle (shoulders, ankles), the diagonal between them, so the
// blend follows the crease (armpit, instep) rather than cutting through the
// parent segment.
Vector3d BlendAxis(int joint) {
  const Vector3d child = BoneAxis(joint);
  const int parent = kJoints[joint].parent;
  if (parent < 0) return child;
  const Vector3d up = BoneAxis(parent);
  if (std::abs(up.dot(child)) > 0.5) return child;
  return (up + child).normalized();
}

struct Geometry {
  std::vector<Vector3d> joints;  // rest positions, world
};

Geometry JointPositions(const BodyShape& shape) {
  Geometry g;
  g.joints.resize(kGenericJointCount);
  for (int j = 0; j < kGenericJointCount; ++j) {
    const JointSpec& js = kJoints[j];
    const Vector3d own(js.x, js.y, js.z);
    if (js.parent < 0) {
      g.joints[j] = own * shape.stature;
      continue;
    }
    // The offset from the parent joint lies inside the parent's segment: its
    // component along that segment's axis scales with length, the rest with girth.
    const Vector3d offset =
        own - Vector3d(kJoints[js.parent].x, kJoints[js.parent].y, kJoints[js.parent].z);
    const int ps = SegmentOfBone(js.parent);
    const Vector3d a = BoneAxis(js.parent);
    const Vector3d axial = a * a.dot(offset);
    g.joints[j] = g.joints[js.parent] +
                  shape.stature * (axial * shape.length[ps] + (offset - axial) * shape.girth[ps]);
  }
  return g;
}

// Skin weights of a vertex of `segment` at rest position p: its bone, blended
// with the parent bone across its own joint and with each child bone across the
// child's joint (within the child's radius of that joint's axis).
std::map<int, double> SkinWeights(int segment, const Vector3d& p, const Geometry& g,
                                  const BodyShape& shape) {
  const int b = Segments()[segment].bone;
  std::map<int, double> w{{b, 1.0}};
  auto across = [&](int joint) {  // 0 behind the joint, 1 past it, 0.5 at it
    const double half = kJoints[joint].blend * shape.stature;
    return SmoothStep(-half, half, BlendAxis(joint).dot(p - g.joints[joint]));
  };
  const int parent = kJoints[b].parent;
  if (parent >= 0) {
    const double a = across(b);
    w[b] = a;
    w[parent] = 1 - a;
  }
  // Children take their shares of the bone's weight in parallel (scaled down
  // when they overlap, as at the crotch), so no child is favoured by order.
  std::map<int, double> take;
  double total = 0;
  for (int c = 0; c < kGenericJointCount; ++c) {
    if (kJoints[c].parent != b) continue;
    const Vector3d d = p - g.joints[c];
    const Vector3d axis = BlendAxis(c);
    const double radial = (d - axis * axis.dot(d)).norm();
    double rw, rd;
    ProfileAt(Resolved(SegmentOfBone(c)).profile, 0, &rw, &rd);
    const int cs = SegmentOfBone(c);
    const double r = std::max(rw, rd) * shape.stature * shape.girth[cs] *
                     (cs == kSegHead ? shape.neck_ratio : 1.0);
    take[c] = w[b] * across(c) * (1 - SmoothStep(1.0 * r, 2.5 * r, radial));
    total += take[c];
  }
  const double scale = total > w[b] ? w[b] / total : 1.0;
  for (const auto& [c, t] : take) {
    w[b] -= t * scale;
    w[c] += t * scale;
  }
  return w;
}

void SetWeights(const std::map<int, double>& w, std::array<uint16_t, kMaxInfluences>* joints,
                std::array<uint16_t, kMaxInfluences>* weights) {
  std::vector<std::pair<double, int>> sorted;
  for (const auto& [bone, weight] : w) {
    if (weight > 1e-6) sorted.push_back({weight, bone});
  }
  std::sort(sorted.rbegin(), sorted.rend());
  sorted.resize(std::min<size_t>(sorted.size(), kMaxInfluences));
  double total = 0;
  for (const auto& e : sorted) total += e.first;
  joints->fill(0);
  weights->fill(0);
  int left = 65535;
  for (size_t i = 0; i < sorted.size(); ++i) {
    const int q =
        i + 1 == sorted.size()
            ? left
            : std::min(left, static_cast<int>(std::lround(65535 * sorted[i].first / total)));
    (*joints)[i] = static_cast<uint16_t>(sorted[i].second);
    (*weights)[i] = static_cast<uint16_t>(q);
    left -= q;
  }
}

void AddSegment(int segment, const Geometry& g, const BodyShape& shape, const MeshResolution& res,
                Mesh* m, std::vector<uint32_t>* canonical) {
  const int sides = std::max(6, res.sides);
  const SegmentSpec s = Resolved(segment);
  const Vector3d a = V(s.axis).normalized();
  const Vector3d wdir = V(s.width_dir).normalized();
  const Vector3d ddir = a.cross(wdir);  // W x D = A: counter-clockwise seen from +A
  const double len = shape.stature * shape.length[segment];
  const double girth = shape.stature * shape.girth[segment];
  const Vector3d origin = g.joints[s.bone] + V(s.offset) * shape.stature;
  const double a0 = s.a0 * len, a1 = s.a1 * len;

  // Rings: 3 on the start cap, 12 along the body, 3 on the end cap; then poles.
  struct Ring {
    double axial, profile_s, scale, v;
  };
  std::vector<Ring> rings;
  constexpr int kCapRings = 3;
  const int body_rings = std::max(2, res.rings - 2 * kCapRings);
  double rw0, rd0, rw1, rd1;
  ProfileAt(s.profile, 0, &rw0, &rd0);
  ProfileAt(s.profile, 1, &rw1, &rd1);
  const double cap0 = s.cap0 * 0.5 * (rw0 + rd0) * girth;
  const double cap1 = s.cap1 * 0.5 * (rw1 + rd1) * girth;
  for (int i = 1; i <= kCapRings; ++i) {
    const double phi = 0.5 * kPi * i / (kCapRings + 1);
    rings.push_back({a0 - cap0 * std::cos(phi), 0, std::sin(phi), 0});
  }
  for (int i = 0; i < body_rings; ++i) {
    // Cosine spacing: rings are densest near the joints, where skinning bends them.
    const double t = 0.5 - 0.5 * std::cos(kPi * i / (body_rings - 1));
    rings.push_back({a0 + t * (a1 - a0), t, 1.0, 0});
  }
  for (int i = kCapRings; i >= 1; --i) {
    const double phi = 0.5 * kPi * i / (kCapRings + 1);
    rings.push_back({a1 + cap1 * std::cos(phi), 1, std::sin(phi), 0});
  }
  for (size_t r = 0; r < rings.size(); ++r) rings[r].v = (r + 1.0) / (rings.size() + 1.0);

  // Chart cell of this segment, with a margin so texels do not bleed across charts.
  const double cell = 0.25, margin = 0.012;
  const double u0 = (segment % 4) * cell + margin, v0 = (segment / 4) * cell + margin;
  const double span = cell - 2 * margin;

  auto add_vertex = [&](const Vector3d& p, double u, double v, uint32_t canon) {
    m->positions.push_back({float(p.x()), float(p.y()), float(p.z())});
    m->uvs.push_back({float(u0 + u * span), float(v0 + v * span)});
    m->segments.push_back(static_cast<uint8_t>(segment));
    std::array<uint16_t, kMaxInfluences> j, w;
    SetWeights(SkinWeights(segment, p, g, shape), &j, &w);
    m->joints.push_back(j);
    m->weights.push_back(w);
    canonical->push_back(canon);
  };

  const uint32_t base = static_cast<uint32_t>(m->positions.size());
  const int cols = sides + 1;  // the last column repeats the first (u = 1)
  for (size_t r = 0; r < rings.size(); ++r) {
    double rw, rd;
    ProfileAt(s.profile, rings[r].profile_s, &rw, &rd);
    if (segment == kSegHead) {
      // The neck (up to 0.3 along the head) narrows by neck_ratio; the skull
      // keeps the head's girth.
      const double k =
          shape.neck_ratio + (1 - shape.neck_ratio) * SmoothStep(0.3, 0.45, rings[r].profile_s);
      rw *= k, rd *= k;
    }
    rw *= girth * rings[r].scale;
    rd *= girth * rings[r].scale;
    for (int c = 0; c < cols; ++c) {
      const double theta = 2 * kPi * (c % sides) / sides;
      const Vector3d p = origin + a * rings[r].axial + wdir * (rw * std::cos(theta)) +
                         ddir * (rd * std::sin(theta));
      const uint32_t ring_start = base + static_cast<uint32_t>(r * cols);
      add_vertex(p, static_cast<double>(c) / sides, rings[r].v, ring_start + (c % sides));
    }
  }
  const uint32_t pole0 = static_cast<uint32_t>(m->positions.size());
  for (int c = 0; c < sides; ++c) {
    add_vertex(origin + a * (a0 - cap0), (c + 0.5) / sides, 0.0, pole0);
  }
  const uint32_t pole1 = static_cast<uint32_t>(m->positions.size());
  for (int c = 0; c < sides; ++c) {
    add_vertex(origin + a * (a1 + cap1), (c + 0.5) / sides, 1.0, pole1);
  }

  auto at = [&](size_t r, int c) { return base + static_cast<uint32_t>(r * cols + c); };
  for (size_t r = 0; r + 1 < rings.size(); ++r) {
    for (int c = 0; c < sides; ++c) {
      m->triangles.push_back({at(r, c), at(r, c + 1), at(r + 1, c + 1)});
      m->triangles.push_back({at(r, c), at(r + 1, c + 1), at(r + 1, c)});
    }
  }
  const size_t last = rings.size() - 1;
  for (int c = 0; c < sides; ++c) {
    m->triangles.push_back({pole0 + c, at(0, c + 1), at(0, c)});
    m->triangles.push_back({pole1 + c, at(last, c), at(last, c + 1)});
  }
}

// Area-weighted vertex normals, accumulated over positions shared across seams.
void ComputeNormals(const std::vector<uint32_t>& canonical, Mesh* m) {
  std::vector<Vector3d> sum(m->positions.size(), Vector3d::Zero());
  auto pos = [&](uint32_t i) {
    return Vector3d(m->positions[i][0], m->positions[i][1], m->positions[i][2]);
  };
  for (const auto& t : m->triangles) {
    const Vector3d n = (pos(t[1]) - pos(t[0])).cross(pos(t[2]) - pos(t[0]));
    for (uint32_t i : t) sum[canonical[i]] += n;
  }
  m->normals.resize(m->positions.size());
  for (size_t i = 0; i < m->positions.size(); ++i) {
    const Vector3d n = sum[canonical[i]].normalized();
    m->normals[i] = {float(n.x()), float(n.y()), float(n.z())};
  }
}

}  // namespace

const char* GenericJointName(int joint) {
  return joint >= 0 && joint < kGenericJointCount ? kJoints[joint].name : "?";
}
const char* GenericSegmentName(int segment) {
  return segment >= 0 && segment < kGenericSegmentCount ? Segments()[segment].name : "?";
}
int SegmentBone(int segment) { return Segments()[segment].bone; }

Status ValidateBodyShape(const BodyShape& shape) {
  if (!std::isfinite(shape.stature) || shape.stature < 0.5 || shape.stature > 1.4) {
    return Status(
        StatusCode::kInvalidArgument,
        "body shape: stature scale must lie in [0.5, 1.4], got " + std::to_string(shape.stature));
  }
  for (int s = 0; s < kGenericSegmentCount; ++s) {
    const double hi = s == kSegHead ? kMaxHeadScale : kMaxSegmentScale;
    for (double v : {shape.length[s], shape.girth[s]}) {
      if (!std::isfinite(v) || v < 0.5 || v > hi) {
        char range[64];
        std::snprintf(range, sizeof range, " must lie in [0.5, %g], got ", hi);
        return Status(StatusCode::kInvalidArgument, std::string("body shape: scales of segment ") +
                                                        GenericSegmentName(s) + range +
                                                        std::to_string(v));
      }
    }
  }
  if (!std::isfinite(shape.neck_ratio) || shape.neck_ratio < kMinNeckRatio ||
      shape.neck_ratio > 1) {
    char message[96];
    std::snprintf(message, sizeof message, "body shape: neck ratio must lie in [%g, 1], got %g",
                  kMinNeckRatio, shape.neck_ratio);
    return Status(StatusCode::kInvalidArgument, message);
  }
  return Status::Ok();
}

Skeleton MakeGenericSkeleton(const BodyShape& shape) {
  const Geometry g = JointPositions(shape);
  Skeleton skeleton;
  for (int j = 0; j < kGenericJointCount; ++j) {
    const JointSpec& js = kJoints[j];
    Bone bone;
    bone.name = js.name;
    bone.parent = js.parent;
    const Vector3d t = js.parent < 0 ? g.joints[j] : g.joints[j] - g.joints[js.parent];
    bone.rest_translation = {float(t.x()), float(t.y()), float(t.z())};
    bone.order = RotationOrder::kZYX;
    bone.dof_mask = js.dofs;
    for (int k = 0; k < kDofKinds; ++k) {
      if (!(js.dofs & (1u << k))) continue;
      bone.dof_min[k] = IsRotationDof(k) ? float(js.lo[k]) : -50.0f;
      bone.dof_max[k] = IsRotationDof(k) ? float(js.hi[k]) : 50.0f;
    }
    skeleton.bones.push_back(bone);
  }
  return skeleton;
}

BodyModel MakeGenericBody(const BodyShape& shape, const MeshResolution& resolution) {
  const Geometry g = JointPositions(shape);
  BodyModel model;
  model.skeleton = MakeGenericSkeleton(shape);
  std::vector<uint32_t> canonical;
  for (int s = 0; s < kGenericSegmentCount; ++s) {
    AddSegment(s, g, shape, resolution, &model.mesh, &canonical);
  }
  ComputeNormals(canonical, &model.mesh);
  return model;
}

}  // namespace fvv
