#include "player/playback/requested_gops.h"

#include <algorithm>

namespace fvv {

RequestedGops::RequestedGops(uint32_t frame_count, uint32_t gop_frames)
    : gops_(gop_frames ? (frame_count + gop_frames - 1) / gop_frames : 0),
      gop_frames_(std::max(1u, gop_frames)) {}

void RequestedGops::Ask(uint32_t gop, const GopRequest& request, bool urgent) {
  if (gop >= gops_ || held_.count(gop) || gop == in_flight_ || decoding_.count(gop)) return;
  auto it = std::find_if(queue_.begin(), queue_.end(),
                         [gop](const Pending& p) { return p.gop == gop; });
  if (it != queue_.end()) {
    if (!urgent || it == queue_.begin()) return;
    queue_.erase(it);
  }
  if (urgent) {
    last_ = request;
    queue_.push_front({gop, request});
  } else {
    queue_.push_back({gop, request});
  }
  // Requests far behind the newest urgent one are stale (the playhead moved).
  while (queue_.size() > kAhead + 1) queue_.pop_back();
}

bool RequestedGops::Ready(uint32_t frame, const GopRequest&) {
  return held_.count(frame / gop_frames_) != 0;
}

void RequestedGops::Prefetch(uint32_t frame, const GopRequest& request) {
  Ask(frame / gop_frames_, request, /*urgent=*/true);
}

StatusOr<bool> RequestedGops::Take(uint32_t frame, const GopRequest& request,
                                   fvv_decode_report* report) {
  const uint32_t gop = frame / gop_frames_;
  auto it = held_.find(gop);
  if (it == held_.end()) {
    Ask(gop, request, /*urgent=*/true);
    return false;
  }
  *report = it->second;
  shown_gop_ = gop;
  last_ = request;
  for (uint32_t g = gop + 1; g <= gop + kAhead && g < gops_; ++g) Ask(g, request, false);
  return true;
}

bool RequestedGops::NextRequest(uint32_t* gop, GopRequest* request) {
  if (in_flight_ != UINT32_MAX || queue_.empty()) return false;
  *gop = queue_.front().gop;
  *request = queue_.front().request;
  queue_.pop_front();
  in_flight_ = *gop;
  return true;
}

void RequestedGops::Fetched(uint32_t gop) {
  if (gop != in_flight_) return;
  in_flight_ = UINT32_MAX;
  decoding_.insert(gop);
}

void RequestedGops::Deliver(uint32_t gop, const fvv_decode_report& report) {
  held_[gop] = report;
  decoding_.erase(gop);
  if (gop == in_flight_) in_flight_ = UINT32_MAX;
  // The network stays busy: the next GOP, while it is within reach of the one shown.
  if (gop + 1 < gops_ && gop + 1 <= shown_gop_ + kAhead) Ask(gop + 1, last_, false);
}

void RequestedGops::Failed(uint32_t gop) {
  if (gop == in_flight_) in_flight_ = UINT32_MAX;
  decoding_.erase(gop);
}

void RequestedGops::Forget(uint32_t gop) { held_.erase(gop); }

}  // namespace fvv
