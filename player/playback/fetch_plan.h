// What a player fetching a stream over HTTP takes of the next GOP: a prefix of
// each fragment its view needs (SPEC.md 3.5.1), as much as the bandwidth it
// measured allows in the time the GOP plays. Numbers only: the web player and
// any native streaming player share it (docs/player.md, "Fetching over HTTP").
#ifndef FVV_PLAYER_PLAYBACK_FETCH_PLAN_H_
#define FVV_PLAYER_PLAYBACK_FETCH_PLAN_H_

#include <cstdint>
#include <vector>

namespace fvv {

// The network's throughput, from the fetches a player made.
class BandwidthEstimate {
 public:
  // `bytes_per_second`: an estimate to go on from (0: none yet).
  explicit BandwidthEstimate(double bytes_per_second = 0) : rate_(bytes_per_second) {}
  // A fetch of `bytes` that took `seconds`, from its request to its last byte.
  void Measured(uint64_t bytes, double seconds);
  // Bytes per second, smoothed over the fetches (a new one weighs 30 %); 0
  // before any.
  double bytes_per_second() const { return rate_; }

 private:
  double rate_;
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
