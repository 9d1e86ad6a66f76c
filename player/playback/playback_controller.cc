#include "player/playback/playback_controller.h"

#include <algorithm>

namespace fvv {

PlaybackController::PlaybackController(double fps, uint32_t gop_frames, double decode_share)
    : gop_ms_(1000.0 * gop_frames / fps),
      gop_frames_(gop_frames),
      share_(decode_share),
      target_ms_(gop_ms_ * decode_share) {}

void PlaybackController::set_speed(double speed) { speed_ = std::max(0.05, speed); }

void PlaybackController::Report(double decode_ms, double render_ms_per_frame, bool complete) {
  // What is left for decoding once this GOP's frames are rendered, with headroom.
  const double play_ms = gop_ms_ / speed_;
  target_ms_ = std::max(1.0, (play_ms - render_ms_per_frame * gop_frames_) * share_);
  // Cutting the embedded streams only shortens their decoding; the transform
  // and the output take what they take. Below this floor, a cut costs much
  // quality (the first bitplanes are the cheap ones) and saves little time, so
  // when even the floor is too slow, playback slows down instead.
  const double floor_ms = std::max(0.5, kFloorShare * target_ms_);
  if (decode_ms > target_ms_) {
    double next;
    if (max_ms_ > 0 && !complete) {
      // Under a budget that cut the decode, the part outside it is fixed:
      // give the streams what is left of the target after it.
      const double fixed_ms = std::max(0.0, decode_ms - max_ms_);
      next = std::min(max_ms_ * 0.95, target_ms_ - fixed_ms);
    } else {
      // First cut: scale by how far off the whole decode was; converges from
      // above over a few GOPs.
      next = (max_ms_ > 0 ? max_ms_ : decode_ms) * target_ms_ / decode_ms * 0.95;
    }
    max_ms_ = std::max(floor_ms, next);
  } else if (max_ms_ > 0) {
    // Keeping up: give quality back; drop the limit once a decode under it
    // completes with room to spare.
    if (complete && decode_ms < 0.8 * target_ms_) {
      max_ms_ = 0;
    } else if (decode_ms < 0.9 * target_ms_) {  // a dead band keeps it from oscillating
      max_ms_ = std::min(max_ms_ * 1.1, target_ms_);
    }
  }
}

}  // namespace fvv
