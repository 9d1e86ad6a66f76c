// What a player fetching a stream over HTTP takes of the next GOP: a prefix of
// each fragment its view needs (SPEC.md 3.5.1), as much as the bandwidth it
// measured allows in the time the GOP plays. Numbers only: the web player and
// any native streaming player share it (docs/player.md, "Fetching over HTTP").
#ifndef FVV_PLAYER_PLAYBACK_FETCH_PLAN_H_
#define FVV_PLAYER_PLAYBACK_FETCH_PLAN_H_

#include <cstdint>
#include <vector>

namespace fvv {

// The network's throughput, from the fetches a player made: their bytes and
// their times, each smoothed over the fetches (a new one weighs 30 %), and
// divided. A ratio of sums, not a mean of each fetch's rate: fetches that
// overlap split the link's time between them unevenly (one that ends just
// after another gets little time for all its bytes), and only their sums
// tell the link's rate.
class BandwidthEstimate {
 public:
  // `bytes_per_second`: an estimate to go on from (0: none yet), weighing as
  // one second of fetching.
  explicit BandwidthEstimate(double bytes_per_second = 0)
      : bytes_(bytes_per_second), seconds_(bytes_per_second > 0 ? 1.0 : 0.0) {}
  // A fetch of `bytes` that took `seconds`: from its request, or from the
  // end of the fetch before it if that ended later, to its last byte.
  void Measured(uint64_t bytes, double seconds);
  // Bytes per second; 0 before any fetch.
  double bytes_per_second() const { return seconds_ > 0 ? bytes_ / seconds_ : 0; }

 private:
  double bytes_, seconds_;
};

// The bytes a GOP's fetch may take: what the bandwidth brings while the GOP
// before it plays, less a margin for the requests' own time and the
// bandwidth's swings.
uint64_t GopFetchBudget(double bytes_per_second, double gop_seconds, double share = 0.9);

// A fragment the view needs, as the index gives it (fvv_fragment_info).
struct FragmentSizes {
  uint64_t head = 0;  // the least prefix that decodes
  uint64_t size = 0;  // the whole fragment
  // The surface's bytes right past the head (fvv_fragment_info.surface_size,
  // or the last GOP's where this one's is not known yet); 0: none.
  uint64_t surface = 0;
};

// The prefix of each fragment to fetch, together at most `budget` bytes: each
// fragment's head first (its motion and masks decode whatever its texture
// gets); then each surface whole where the budget holds it (it decodes whole
// or not at all, and a fragment's texture lies past it: a fragment whose
// surface does not fit stops at its head); then the texture bytes shared in
// proportion to each fragment's texture, so that every camera decodes about
// the same share of its streams, none past its size. Whole fragments when the
// budget holds them; heads only when even those exceed it (the caller then
// waits for them).
std::vector<uint64_t> PlanPrefixes(const std::vector<FragmentSizes>& fragments, uint64_t budget);

}  // namespace fvv

#endif  // FVV_PLAYER_PLAYBACK_FETCH_PLAN_H_
