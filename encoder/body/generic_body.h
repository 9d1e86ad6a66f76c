// The generic human body model: 16 body segments, 17 joints and 35
// pose degrees of freedom, each segment a closed triangle mesh (23,040 triangles
// in all), skinned smoothly across every joint so bent limbs show no gaps.
// Built in code: no data files. Per-segment length and girth scales (stature and
// build) adapt it to an actor; tracking keeps them fixed.
//
// Conventions: metres, world Y up, the actor faces +Z in the rest pose (a
// T-pose, arms along +-X), its left side is +X. Every bone rotates in Euler
// order ZYX about its rest axes (Bone::order).
#ifndef FVV_ENCODER_BODY_GENERIC_BODY_H_
#define FVV_ENCODER_BODY_GENERIC_BODY_H_

#include <array>
#include <string>

#include "codec/base/status.h"
#include "container/body_model.h"

namespace fvv {

// Bone (joint) indices. The root carries the 6-DOF global placement; kHead is
// the upper neck joint (the head segment spans kNeck and kHead).
enum GenericJoint : int {
  kRoot = 0,
  kLumbar,
  kThoracic,
  kNeck,
  kHead,
  kLeftShoulder,
  kLeftElbow,
  kLeftWrist,
  kRightShoulder,
  kRightElbow,
  kRightWrist,
  kLeftHip,
  kLeftKnee,
  kLeftAnkle,
  kRightHip,
  kRightKnee,
  kRightAnkle,
  kGenericJointCount  // 17
};

enum GenericSegment : int {
  kSegPelvis = 0,
  kSegAbdomen,
  kSegChest,
  kSegHead,
  kSegLeftUpperArm,
  kSegLeftForearm,
  kSegLeftHand,
  kSegRightUpperArm,
  kSegRightForearm,
  kSegRightHand,
  kSegLeftThigh,
  kSegLeftShank,
  kSegLeftFoot,
  kSegRightThigh,
  kSegRightShank,
  kSegRightFoot,
  kGenericSegmentCount  // 16
};

constexpr int kGenericDofCount = 35;
// Mesh resolution per segment: rings along the axis and vertices around it.
// The full model (what is rendered and coded) has 18 x 40; tracking uses a
// coarser mesh of the same shape (its silhouettes differ by under a pixel).
constexpr int kSegmentRings = 18;
constexpr int kSegmentSides = 40;
struct MeshResolution {
  int rings = kSegmentRings;  // >= 8 (3 per end cap, the rest along the body)
  int sides = kSegmentSides;  // >= 6
};

const char* GenericJointName(int joint);
const char* GenericSegmentName(int segment);
// The bone a segment's vertices mostly follow.
int SegmentBone(int segment);

// Stature and build: every rest offset inside a segment is scaled by
// stature * length[segment]; every cross-section radius by girth[segment].
struct BodyShape {
  double stature = 1.0;  // 1.0 = 1.75 m tall
  std::array<double, kGenericSegmentCount> length;
  std::array<double, kGenericSegmentCount> girth;
  // The neck's girth as a fraction of the head's: a cartoon character's
  // large head sits on a neck no wider than a person's.
  double neck_ratio = 1.0;
  BodyShape() {
    length.fill(1.0);
    girth.fill(1.0);
  }
};

// Largest length or girth scale of a segment. The head's range is wider:
// cartoon characters (CesiumMan) have heads twice and more as wide as a
// person's at the same height.
constexpr double kMaxSegmentScale = 2.0;
constexpr double kMaxHeadScale = 3.0;
// The thinnest neck, as a fraction of the head's girth.
constexpr double kMinNeckRatio = 0.3;

// Checks scales are finite and within [0.5, kMaxSegmentScale] (the head's
// within [0.5, kMaxHeadScale]; stature within [0.5, 1.4]; the neck ratio
// within [kMinNeckRatio, 1]).
Status ValidateBodyShape(const BodyShape& shape);

// The model in its rest pose: skeleton (names above, DOF limits on every DOF),
// mesh with per-segment charts in a 4x4 grid of the unit UV square (segment s
// in cell (s % 4, s / 4)); a chart's u runs around the segment, v along it.
// Each chart column at u = 1 duplicates the one at u = 0, and each pole is one
// vertex per column, so positions are shared exactly across those seams.
BodyModel MakeGenericBody(const BodyShape& shape = BodyShape(),
                          const MeshResolution& resolution = MeshResolution());

// The skeleton alone (what MakeGenericBody's model has), cheap enough to
// build inside a fit that varies the shape.
Skeleton MakeGenericSkeleton(const BodyShape& shape = BodyShape());

}  // namespace fvv

#endif  // FVV_ENCODER_BODY_GENERIC_BODY_H_
