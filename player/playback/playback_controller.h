// Real-time quality control of the player: each GOP's textures are decoded
// under a time budget (progressive SPIHT truncation) sized from what was
// measured while the previous GOPs played, above a quality floor that no load
// cuts through. When even the floor takes longer than a GOP plays, playback
// slows down (the player holds the playhead) instead of showing untextured
// frames; when decoding gets cheap again the budget grows back within a GOP.
//
// One policy for every player (the native one, the web one): it sees times and
// byte counts only, no decoder and no GL. docs/player.md explains it with a
// plot of a load step.
#ifndef FVV_PLAYER_PLAYBACK_PLAYBACK_CONTROLLER_H_
#define FVV_PLAYER_PLAYBACK_PLAYBACK_CONTROLLER_H_

#include <cstdint>

namespace fvv {

// What happened to one GOP, as the player measured it.
struct GopOutcome {
  double decode_ms = 0;  // wall time of its decode (under the budget it was given)
  double budget_ms = 0;  // the time budget it was decoded under; 0 = none
  bool complete = true;  // every stream decoded to its end
  double wait_ms = 0;    // how long the playhead waited for it (0: it was ready in time)
  double frame_ms = 0;   // the player's own time per frame (upload, draw), smoothed
  uint32_t cameras = 0;  // the cameras it decoded (0: not known)
};

class PlaybackController {
 public:
  // The share of each texture stream decoded under any load: the first
  // bitplanes of luma and chroma (docs/player.md: why 0.15).
  static constexpr double kDefaultFloorShare = 0.15;

  PlaybackController(double fps, uint32_t gop_frames, double floor_share = kDefaultFloorShare);

  // Time budget (ms) for the next GOP's texture decoding. Always a time budget
  // (a real-time player's mode, SPEC.md B.2): a GOP that fits is decoded whole.
  double NextMaxMs() const { return max_ms_; }
  // The floor to pass with it (fvv_decode_budget.floor_share).
  double floor_share() const { return floor_share_; }
  void Report(const GopOutcome& gop);

  // What a GOP's decode may take: its play time less the reserve.
  double target_ms() const { return target_ms_; }
  // Kept back from each GOP's play time for what shares the cores with the
  // decode, grown by every wait the player measured and shrunk while none come.
  double reserve_ms() const { return reserve_ms_; }
  // The decode's share that no budget shortens (transform, masks, output),
  // measured from decodes the deadline cut.
  double fixed_ms() const { return fixed_ms_; }
  // The fewest cameras a limit leaves: the blend's closest three (ViewCameras).
  static constexpr uint32_t kMinCameras = 3;
  // The share of the target that the floor of the cameras decoded may take,
  // leaving the rest for bitplanes above it.
  static constexpr double kFloorShareOfTarget = 0.75;
  // The most cameras the next GOPs should decode, 0 for no limit: as many as
  // the measured time per camera that no budget shortens fits in
  // kFloorShareOfTarget of the target, at least kMinCameras. Every camera
  // decoded costs its transform and its floor whatever the budget, so when
  // even the floor of the cameras a view wants takes longer than a GOP
  // plays, fewer cameras (the closest, which the blend weighs most) keep
  // playback in real time where the budget alone could not.
  // Before any GOP was reported, the closest three: the first GOPs decode
  // while nothing is measured and the first frames are drawn, and the start
  // waits for them.
  uint32_t max_cameras() const;
  // Even the floor did not keep up with the last GOP: playback is slower than
  // real time (the HUD says so).
  bool below_real_time() const { return below_real_time_; }
  // The next budget is the smallest: the floor alone decides what is decoded.
  bool at_floor() const;
  void set_speed(double speed);  // playback speed factor: GOPs come faster

 private:
  double gop_ms_;
  double floor_share_;
  double speed_ = 1.0;
  double target_ms_;
  double reserve_ms_;
  double fixed_ms_ = -1;   // < 0: not measured yet
  double camera_ms_ = -1;  // < 0: not measured yet
  bool reported_ = false;  // a GOP's outcome came in
  double max_ms_;
  bool below_real_time_ = false;
};

}  // namespace fvv

#endif  // FVV_PLAYER_PLAYBACK_PLAYBACK_CONTROLLER_H_
