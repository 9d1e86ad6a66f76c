// Real-time quality control of the player: when decoding a GOP takes longer than
// the share of its play time the player can give it, the next GOPs are decoded
// under a time budget (progressive SPIHT truncation) instead of dropping frames;
// when decoding gets cheap again the budget grows back to a full decode.
#ifndef FVV_PLAYER_PLAYBACK_PLAYBACK_CONTROLLER_H_
#define FVV_PLAYER_PLAYBACK_PLAYBACK_CONTROLLER_H_

#include <cstdint>

namespace fvv {

class PlaybackController {
 public:
  // decode_share: the part of the time a GOP plays, less its frames' render
  // time, that decoding may use (the rest is headroom for uploads, the display
  // and timing noise).
  PlaybackController(double fps, uint32_t gop_frames, double decode_share = 0.8);

  // Time budget (ms) for the next GOP's texture decoding; 0 = decode everything.
  double NextMaxMs() const { return max_ms_; }
  // After each GOP: how long its decode took, the render time per frame, and
  // whether the decode was complete (not cut by the budget).
  void Report(double decode_ms, double render_ms_per_frame, bool complete);

  double target_ms() const { return target_ms_; }
  // The smallest time budget, as a share of the target: never cut the streams
  // to nothing when the fixed costs alone miss the target.
  static constexpr double kFloorShare = 0.2;
  void set_speed(double speed);  // playback speed factor: GOPs come faster

 private:
  double gop_ms_;
  uint32_t gop_frames_;
  double share_;
  double speed_ = 1.0;
  double target_ms_;
  double max_ms_ = 0;  // 0: unlimited
};

}  // namespace fvv

#endif  // FVV_PLAYER_PLAYBACK_PLAYBACK_CONTROLLER_H_
