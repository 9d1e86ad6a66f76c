#include "player/playback/playback_controller.h"

#include <algorithm>

namespace fvv {
namespace {

// The smallest time budget: below it the floor decides what is decoded anyway.
constexpr double kMinBudgetMs = 1;
// Without waits the reserve shrinks by this factor a GOP, so that quality comes
// back within a few GOPs of a load going away.
constexpr double kReserveDecay = 0.5;
// The budget's largest rise from one GOP to the next.
constexpr double kMaxRise = 4;
constexpr double kRiseStepMs = 20;

}  // namespace

PlaybackController::PlaybackController(double fps, uint32_t gop_frames, double floor_share)
    : gop_ms_(1000.0 * gop_frames / fps),
      floor_share_(std::min(1.0, std::max(0.0, floor_share))),
      target_ms_(gop_ms_),
      reserve_ms_(0),
      max_ms_(gop_ms_) {}

uint32_t PlaybackController::max_cameras() const {
  if (!reported_) return kMinCameras;
  if (camera_ms_ <= 0) return 0;
  const double fits = kFloorShareOfTarget * target_ms_ / camera_ms_;
  if (fits >= 64) return 0;
  return std::max(kMinCameras, static_cast<uint32_t>(fits));
}

bool PlaybackController::at_floor() const { return max_ms_ <= 2 * kMinBudgetMs; }

void PlaybackController::set_speed(double speed) { speed_ = std::max(0.05, speed); }

void PlaybackController::Report(const GopOutcome& gop) {
  reported_ = true;
  // The next GOP is decoded while this one plays, so it has this one's play
  // time, less what shares the cores with it. That share is measured: a GOP the
  // playhead waited for was late by the wait, so the reserve grows by it; while
  // none is late it shrinks towards the frame that shows a new GOP (which also
  // uploads its textures).
  const double play_ms = gop_ms_ / speed_;
  const double min_reserve = gop.frame_ms;
  // A wait under the smallest budget came from the floor, which no reserve
  // shortens: it slows playback instead.
  const bool floor_only = gop.budget_ms > 0 && gop.budget_ms <= 2 * kMinBudgetMs;
  if (gop.wait_ms > 0 && !floor_only) {
    reserve_ms_ += gop.wait_ms;
  } else if (gop.wait_ms == 0) {
    reserve_ms_ *= kReserveDecay;
  }
  reserve_ms_ = std::min(0.9 * play_ms, std::max(min_reserve, reserve_ms_));
  target_ms_ = std::max(kMinBudgetMs, play_ms - reserve_ms_);

  // What a budget does not shorten: the decode's time beyond the budget when
  // the deadline cut it (set-up, the floor's bytes, transform, masks, output).
  if (gop.budget_ms > 0 && !gop.complete) {
    // Down at once (a load went away: quality comes back with the next GOP),
    // up smoothed (one slow GOP is not yet a load).
    const double fixed = std::max(0.0, gop.decode_ms - gop.budget_ms);
    fixed_ms_ = fixed_ms_ < 0 || fixed < fixed_ms_ ? fixed : 0.5 * fixed_ms_ + 0.5 * fixed;
    // The same per camera decoded, for the cameras' limit: alike.
    if (gop.cameras > 0) {
      const double per = fixed / gop.cameras;
      camera_ms_ = camera_ms_ < 0 || per < camera_ms_ ? per : 0.5 * camera_ms_ + 0.5 * per;
    }
  } else if (gop.complete && gop.cameras > 0 && camera_ms_ >= 0) {
    // A whole decode took at most this per camera, its fixed part less.
    camera_ms_ = std::min(camera_ms_, gop.decode_ms / gop.cameras);
  }
  below_real_time_ = gop.decode_ms > play_ms || gop.wait_ms > 0.5 * play_ms;

  // The budget is wall time, so the streams' decoding gets what is left of the
  // target whatever the load: more bytes as soon as the cores are free again,
  // the whole GOP when it fits.
  // It falls at once but rises at most to twice what it was (and a little):
  // one cheap GOP under load would otherwise swing quality from the floor to
  // whole decodes and back.
  const double wanted = std::max(kMinBudgetMs, target_ms_ - std::max(0.0, fixed_ms_));
  max_ms_ = std::min(wanted, kMaxRise * max_ms_ + kRiseStepMs);
}

}  // namespace fvv
