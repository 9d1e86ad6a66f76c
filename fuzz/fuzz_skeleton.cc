#include "fuzz/fuzz_skeleton.h"

namespace fvv {

const Skeleton& FuzzSkeleton() {
  static const Skeleton skeleton = [] {
    // Same DOF layout as the sample body model (conformance/sample), without
    // linking the encoder into a decoder-side target.
    const uint8_t dofs[15] = {0x3F, 7, 3, 7, 2, 5, 7, 2, 5, 7, 1, 5, 7, 1, 5};
    const int parents[15] = {-1, 0, 1, 1, 3, 4, 1, 6, 7, 0, 9, 10, 0, 12, 13};
    Skeleton s;
    for (int b = 0; b < 15; ++b) {
      Bone bone;
      bone.name = "b" + std::to_string(b);
      bone.parent = parents[b];
      bone.dof_mask = dofs[b];
      s.bones.push_back(bone);
    }
    return s;
  }();
  return skeleton;
}

}  // namespace fvv
