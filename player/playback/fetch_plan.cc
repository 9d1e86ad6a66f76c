#include "player/playback/fetch_plan.h"

#include <algorithm>

namespace fvv {

void BandwidthEstimate::Measured(uint64_t bytes, double seconds) {
  if (!(seconds > 0) || bytes == 0) return;
  const double rate = double(bytes) / seconds;
  rate_ = rate_ == 0 ? rate : 0.7 * rate_ + 0.3 * rate;
}

uint64_t GopFetchBudget(double bytes_per_second, double gop_seconds, double share) {
  const double bytes = bytes_per_second * gop_seconds * share;
  return bytes > 0 ? uint64_t(bytes) : 0;
}

std::vector<uint64_t> PlanPrefixes(const std::vector<FragmentSizes>& fragments, uint64_t budget) {
  std::vector<uint64_t> prefix(fragments.size());
  uint64_t heads = 0, texture = 0;
  for (size_t i = 0; i < fragments.size(); ++i) {
    const FragmentSizes& f = fragments[i];
    prefix[i] = std::min(f.head, f.size);
    heads += prefix[i];
    texture += f.size - prefix[i];
  }
  if (budget <= heads || texture == 0) return prefix;
  const uint64_t left = budget - heads;
  if (left >= texture) {
    for (size_t i = 0; i < fragments.size(); ++i) prefix[i] = fragments[i].size;
    return prefix;
  }
  // The same share of every fragment's texture (integer arithmetic: the sum
  // never passes the budget).
  for (size_t i = 0; i < fragments.size(); ++i) {
    const uint64_t t = fragments[i].size - prefix[i];
    prefix[i] += uint64_t((unsigned __int128)t * left / texture);
  }
  return prefix;
}

}  // namespace fvv
