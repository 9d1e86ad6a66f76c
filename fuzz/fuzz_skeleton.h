// The skeleton the motion fuzz target decodes with: 15 bones, 35 DOF, fixed so
// that seeds stay meaningful.
#ifndef FVV_FUZZ_FUZZ_SKELETON_H_
#define FVV_FUZZ_FUZZ_SKELETON_H_

#include "container/body_model.h"

namespace fvv {
const Skeleton& FuzzSkeleton();
}  // namespace fvv

#endif  // FVV_FUZZ_FUZZ_SKELETON_H_
