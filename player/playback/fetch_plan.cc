#include "player/playback/fetch_plan.h"

#include <algorithm>

namespace fvv {

void BandwidthEstimate::Measured(uint64_t bytes, double seconds) {
  if (!(seconds > 0) || bytes == 0) return;
  if (seconds_ == 0) {
    bytes_ = double(bytes);
    seconds_ = seconds;
    return;
  }
  bytes_ = 0.7 * bytes_ + 0.3 * double(bytes);
  seconds_ = 0.7 * seconds_ + 0.3 * seconds;
}

uint64_t GopFetchBudget(double bytes_per_second, double gop_seconds, double share) {
  const double bytes = bytes_per_second * gop_seconds * share;
  return bytes > 0 ? uint64_t(bytes) : 0;
}

std::vector<uint64_t> PlanPrefixes(const std::vector<FragmentSizes>& fragments, uint64_t budget) {
  const size_t n = fragments.size();
  std::vector<uint64_t> prefix(n);
  uint64_t used = 0;
  for (size_t i = 0; i < n; ++i) {
    prefix[i] = std::min(fragments[i].head, fragments[i].size);
    used += prefix[i];
  }
  if (budget <= used) return prefix;
  // Each surface whole where it fits; a fragment whose surface does not
  // stops at its head (its texture lies past the surface).
  std::vector<uint8_t> open(n, 1);
  for (size_t i = 0; i < n; ++i) {
    const uint64_t s = std::min(fragments[i].surface, fragments[i].size - prefix[i]);
    if (s == 0) continue;
    if (used + s <= budget) {
      prefix[i] += s;
      used += s;
    } else {
      open[i] = 0;
    }
  }
  uint64_t texture = 0;
  for (size_t i = 0; i < n; ++i) texture += open[i] ? fragments[i].size - prefix[i] : 0;
  if (texture == 0) return prefix;
  const uint64_t left = budget - used;
  if (left >= texture) {
    for (size_t i = 0; i < n; ++i) prefix[i] = open[i] ? fragments[i].size : prefix[i];
    return prefix;
  }
  // The same share of every open fragment's texture (integer arithmetic: the
  // sum never passes the budget).
  for (size_t i = 0; i < n; ++i) {
    if (!open[i]) continue;
    const uint64_t t = fragments[i].size - prefix[i];
    prefix[i] += uint64_t((unsigned __int128)t * left / texture);
  }
  return prefix;
}

}  // namespace fvv
