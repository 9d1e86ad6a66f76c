#include "encoder/encode/sample_agreement.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace fvv {

SampleAgreementCount DropDisagreeingSamples(uint32_t cameras, size_t texels,
                                            const uint32_t* texel_list, size_t count,
                                            const uint8_t* rgb, uint8_t* mask,
                                            const SampleAgreementOptions& o,
                                            const uint8_t* suspects) {
  SampleAgreementCount r;
  std::vector<uint32_t> seen;
  std::vector<uint32_t> drop;
  const double limit = 3 * o.max_difference;  // on the sum over the channels
  for (size_t e = 0; e < count; ++e) {
    const size_t t = texel_list[e];
    seen.clear();
    for (uint32_t c = 0; c < cameras; ++c) {
      if (mask[c * texels + t]) seen.push_back(c);
    }
    if (suspects) {
      // A suspect camera alone on a texel: nothing backs it.
      if (seen.size() == 1 && suspects[seen[0]]) {
        mask[seen[0] * texels + t] = 0;
        ++r.voted, ++r.dropped;
        continue;
      }
      if (seen.size() < 2) continue;
    } else if (seen.size() < std::max(o.min_cameras, 2u)) {
      continue;
    }
    ++r.voted;
    // A sample is kept where another camera saw the same colour: the cameras
    // that saw the actor back each other, the one that saw something else has
    // none backing it.
    for (uint32_t c : seen) {
      if (suspects && !suspects[c]) continue;
      const uint8_t* p = &rgb[(c * texels + t) * 3];
      bool backed = false;
      for (uint32_t k : seen) {
        if (k == c) continue;
        const uint8_t* q = &rgb[(k * texels + t) * 3];
        const int d = std::abs(p[0] - q[0]) + std::abs(p[1] - q[1]) + std::abs(p[2] - q[2]);
        if (d <= limit) {
          backed = true;
          break;
        }
      }
      if (!backed) drop.push_back(c);
    }
    for (uint32_t c : drop) mask[c * texels + t] = 0;
    r.dropped += drop.size();
    drop.clear();
  }
  return r;
}

}  // namespace fvv
