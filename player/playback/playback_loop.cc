#include "player/playback/playback_loop.h"

#include <algorithm>
#include <bitset>
#include <cmath>
#include <glm/gtc/quaternion.hpp>
#include <string>
#include <utility>

#include "player/playback/view_cameras.h"

namespace fvv {

PlaybackLoop::PlaybackLoop(FrameSource* source, const fvv_stream_info& info,
                           std::vector<glm::vec3> centres, double floor_share)
    : source_(source),
      info_(info),
      centres_(std::move(centres)),
      fps_(double(info.frame_rate_num) / info.frame_rate_den),
      control_(fps_, info.gop_frames, floor_share) {}

const fvv_decode_report& PlaybackLoop::report() const { return report_; }

void PlaybackLoop::FetchMeasured(uint64_t bytes, double seconds) {
  bandwidth_.Measured(bytes, seconds);
  stats_.bytes_fetched += bytes;
  // Each fetch in while none is late takes the share up too, not only each
  // GOP shown: the first GOPs are fetched far ahead of the playhead.
  if (!fetch_late_) fetch_share_ = std::min(kSteadyFetchShare, fetch_share_ + 0.05);
}

uint64_t PlaybackLoop::FetchBudget() const {
  const double rate = bandwidth_.bytes_per_second();
  if (rate <= 0) return 0;
  return std::max<uint64_t>(
      1, GopFetchBudget(rate, info_.gop_frames / (fps_ * transport_.speed), FetchShare()));
}

double PlaybackLoop::FetchShare() const {
  if (fetch_share_ < kSteadyFetchShare) return fetch_share_;
  const double fill = std::clamp((fetch_filled_ - 0.5) / 0.5, 0.0, 1.0);
  return kSteadyFetchShare + (kMaxFetchShare - kSteadyFetchShare) * fill;
}

void PlaybackLoop::Seek(uint32_t frame) {
  if (info_.frame_count == 0) return;
  transport_.playhead = std::min(frame, info_.frame_count - 1);
  waiting_ = true;
  preroll_due_ = true;
}

uint64_t PlaybackLoop::ViewMask(const glm::vec3& eye, const glm::vec3& target) {
  if (all_cameras) return 0;
  // The GOP asked for now is shown one to two GOPs later (it is decoded ahead),
  // so the cameras reach further round the actor by twice the angle the view
  // turned since the last GOP's cameras were picked.
  const glm::vec3 direction = glm::normalize(eye - target);
  float turned_deg = 0;
  if (glm::length(last_direction_) > 0) {
    const float cosine = std::clamp(glm::dot(direction, last_direction_), -1.0f, 1.0f);
    turned_deg = glm::degrees(std::acos(cosine));
  }
  const float reach = std::min(180.0f, 90.0f + 2 * turned_deg);
  // The closest cameras are capped (kMaxViewCameras, or fewer where the
  // decoder cannot keep up with more: PlaybackController::max_cameras).
  const uint32_t limit = control_.max_cameras();
  const int most =
      limit ? std::min<int>(kMaxViewCameras, static_cast<int>(limit)) : kMaxViewCameras;
  uint64_t mask = ViewCameras(centres_, eye, target, reach, 3, most);
  // While the view turns, the closest to where it will be by then too, the
  // turn carried on twice.
  const glm::vec3 axis = glm::cross(last_direction_, direction);  // 0 before the first view
  if (turned_deg > 1.0f && glm::length(axis) > 1e-6f) {
    const glm::vec3 ahead =
        glm::angleAxis(glm::radians(2 * turned_deg), glm::normalize(axis)) * direction;
    mask |=
        ViewCameras(centres_, target + ahead * glm::length(eye - target), target, reach, 3, most);
  }
  if (limit && static_cast<int>(std::bitset<64>(mask).count()) > most) {
    mask = ClosestCameras(centres_, mask, eye, target, most);
  }
  last_direction_ = direction;
  return mask;
}

uint32_t PlaybackLoop::LastGop() const { return (info_.frame_count - 1) / info_.gop_frames; }

void PlaybackLoop::PrefetchFirstGop(const glm::vec3& eye, const glm::vec3& target) {
  if (!transport_.loop || wrap_asked_ || LastGop() == 0) return;
  wrap_asked_ = true;
  wrap_mask_ = ViewMask(eye, target);
  wrap_mask_set_ = true;
  GopRequest first = Request();
  first.budget.camera_mask = wrap_mask_;
  source_->Prefetch(0, first);
}

GopRequest PlaybackLoop::Request() const {
  GopRequest request;
  request.budget.max_ms_per_gop = control_.NextMaxMs();
  request.budget.floor_share = control_.floor_share();
  request.budget.camera_mask = gop_mask_;
  request.fetch_bytes = FetchBudget();
  return request;
}

Status PlaybackLoop::Advance(double dt, const glm::vec3& eye, const glm::vec3& target) {
  Transport& t = transport_;
  const uint32_t frames = info_.frame_count;
  if (prerolling() && t.playing) {
    preroll_s_ += dt;
    const uint32_t next = shown_ / info_.gop_frames + 1;
    if (next > LastGop() || preroll_s_ >= kMaxPrerollS ||
        source_->Ready(next * info_.gop_frames, Request())) {
      preroll_s_ = -1;
      on_screen_s_ = 0;  // held by the start-up, not by a late GOP
    } else {
      // No frame is taken meanwhile: the GOPs queued ahead learn the latest
      // budget and cameras here instead.
      source_->Retarget(Request());
    }
  }
  // A playhead waiting for a frame (the first, a late GOP's, a seek's) starts
  // from it once it is there, rather than from where the wait's time took it.
  if (t.playing && !waiting_ && !prerolling()) {
    t.playhead += dt * fps_ * t.speed;
    if (t.playhead >= frames) {
      t.playhead = t.loop ? std::fmod(t.playhead, double(frames)) : frames - 1;
      if (!t.loop) t.playing = false;
    }
  }
  if (t.playhead < 0) t.playhead = 0;
  if (t.playhead > frames - 1 + 0.999) t.playhead = frames - 1 + 0.999;
  control_.set_speed(t.speed);
  uint32_t f = static_cast<uint32_t>(t.playhead);
  // The cameras to decode come from the view when a GOP is first asked for,
  // and stay for its frames (a different set would mean decoding it again).
  if (f / info_.gop_frames != mask_gop_) {
    mask_gop_ = f / info_.gop_frames;
    gop_mask_ = mask_gop_ == 0 && wrap_mask_set_ ? wrap_mask_ : ViewMask(eye, target);
    wrap_mask_set_ = false;
  }
  fetch_filled_ = source_->FetchWindowFilled();
  const GopRequest request = Request();
  on_screen_s_ += dt;
  if (f != shown_ && has_frame() && !source_->Ready(f, request)) {
    // Its GOP is still decoding: keep showing the current frame (the view
    // stays interactive) and hold the playhead, so that playback slows down
    // rather than skipping frames or showing them untextured. It waits at the
    // frame wanted, so a seek is not lost while its GOP comes.
    source_->Prefetch(f, request);
    // A wait for bytes still on their way is the network's: the next GOPs
    // take less of the bandwidth until some are ahead again. A wait for a
    // GOP being decoded is the decoder's: the controller's budget answers it.
    const bool network = source_->Arriving(f);
    if (t.playing && !network) wait_ms_ += 1000 * dt;
    if (t.playing && network) fetch_late_ = true;
    if (t.playing && !waiting_) {
      ++stats_.waits;
      if (network) fetch_share_ = std::max(kMinFetchShare, fetch_share_ * 0.7);
    }
    t.playhead = f;
    waiting_ = true;
    f = shown_;
  }
  // Looping: the first GOP is decoded ahead as soon as the last one is, so that
  // it has more time than a short last GOP's few frames (decoding ahead itself
  // stops at the stream's end).
  if (has_frame() && shown_ / info_.gop_frames + 1 == LastGop() &&
      source_->Ready(LastGop() * info_.gop_frames, request)) {
    PrefetchFirstGop(eye, target);
  }
  changed_ = false;
  if (f == shown_) {
    if (shown_ == uint32_t(t.playhead)) waiting_ = false;
    return Status::Ok();
  }
  fvv_decode_report r{};
  FVV_ASSIGN_OR_RETURN(const bool taken, source_->Take(f, request, &r));
  if (!taken) {  // the first frame, not there yet: the playhead waits at it
    t.playhead = f;
    waiting_ = true;
    return Status::Ok();
  }
  changed_ = true;
  waiting_ = false;
  if (preroll_due_) {
    preroll_due_ = false;
    preroll_s_ = 0;
  }
  if (shown_ != UINT32_MAX && t.playing) {
    stats_.frames_advanced += f > shown_ ? f - shown_ : f + frames - shown_;
    if (on_screen_s_ > 2.0 / (fps_ * t.speed)) ++stats_.stalls;
  }
  on_screen_s_ = 0;
  report_ = r;
  const uint32_t gop = f / info_.gop_frames;
  if (gop != last_gop_) {
    last_gop_ = gop;
    GopOutcome outcome;
    outcome.decode_ms = r.decode_ms;
    outcome.budget_ms = r.max_ms_per_gop;
    outcome.complete = r.complete != 0;
    outcome.wait_ms = wait_ms_;
    outcome.frame_ms = frame_ms_;
    outcome.cameras = source_->CamerasTaken();
    const uint32_t limit = control_.max_cameras();
    control_.Report(outcome);
    // Fewer cameras keep up: the GOPs asked for from now on take the closest
    // of this GOP's (a subset, which what was decoded ahead serves). More
    // come with the next GOP's cameras.
    const uint32_t lower = control_.max_cameras();
    if (gop_mask_ != 0 && lower != 0 && (limit == 0 || lower < limit) &&
        std::bitset<64>(gop_mask_).count() > lower) {
      gop_mask_ = ClosestCameras(centres_, gop_mask_, eye, target, static_cast<int>(lower));
      source_->Retarget(Request());
    }
    // Back up towards the bandwidth's whole share while GOPs arrive in time.
    if (!fetch_late_) fetch_share_ = std::min(kSteadyFetchShare, fetch_share_ + 0.1);
    fetch_late_ = false;
    wait_ms_ = 0;
    ++stats_.gops;
    stats_.decode_ms += r.decode_ms;
    stats_.bytes_decoded += r.bytes_decoded;
    stats_.bytes_available += r.bytes_available;
    if (gop == 0) wrap_asked_ = false;
    if (gop == LastGop()) PrefetchFirstGop(eye, target);
  }
  if (r.bytes_available > 0 && r.bytes_decoded == 0) ++stats_.frames_without_texture;
  shown_ = f;
  return Status::Ok();
}

void PlaybackLoop::FrameDrawn(double draw_ms) {
  frame_ms_ = frame_ms_ == 0 ? draw_ms : 0.9 * frame_ms_ + 0.1 * draw_ms;
  ++stats_.frames_drawn;
}

}  // namespace fvv
