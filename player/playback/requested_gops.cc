#include "player/playback/requested_gops.h"

#include <algorithm>
#include <bitset>

namespace fvv {

RequestedGops::RequestedGops(uint32_t frame_count, uint32_t gop_frames, uint32_t fetch_ahead)
    : gops_(gop_frames ? (frame_count + gop_frames - 1) / gop_frames : 0),
      gop_frames_(std::max(1u, gop_frames)),
      fetch_ahead_(std::max(kAhead, fetch_ahead)) {}

void RequestedGops::Ask(uint32_t gop, const GopRequest& request, bool urgent) {
  if (gop >= gops_ || held_.count(gop) || in_flight_.count(gop) || fetched_.count(gop) ||
      gop == decoding_) {
    return;
  }
  auto it =
      std::find_if(queue_.begin(), queue_.end(), [gop](const Pending& p) { return p.gop == gop; });
  if (it != queue_.end()) {
    // Not fetched yet: it takes the latest request (the bandwidth's bytes,
    // the view's cameras), not the one it was first asked with.
    it->request = request;
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
  while (queue_.size() > fetch_ahead_ + 1) queue_.pop_back();
}

bool RequestedGops::Ready(uint32_t frame, const GopRequest&) {
  return held_.count(frame / gop_frames_) != 0;
}

void RequestedGops::Prefetch(uint32_t frame, const GopRequest& request) {
  wanted_ = frame / gop_frames_;
  Ask(wanted_, request, /*urgent=*/true);
}

StatusOr<bool> RequestedGops::Take(uint32_t frame, const GopRequest& request,
                                   fvv_decode_report* report) {
  const uint32_t gop = frame / gop_frames_;
  auto it = held_.find(gop);
  if (it == held_.end()) {
    wanted_ = gop;
    Ask(gop, request, /*urgent=*/true);
    // Its bytes are in and it decodes: the link would idle, so the GOPs
    // after it are fetched meanwhile.
    if (fetched_.count(gop) || gop == decoding_) {
      for (uint32_t g = gop + 1; g <= gop + kAhead && g < gops_; ++g) Ask(g, request, false);
    }
    return false;
  }
  taken_ = true;
  *report = it->second.report;
  cameras_taken_ = it->second.cameras;
  shown_gop_ = gop;
  if (wanted_ == gop) wanted_ = UINT32_MAX;
  last_ = request;
  for (uint32_t g = gop + 1; g <= gop + fetch_ahead_ && g < gops_; ++g) Ask(g, request, false);
  return true;
}

bool RequestedGops::Arriving(uint32_t frame) const {
  const uint32_t gop = frame / gop_frames_;
  return !held_.count(gop) && !fetched_.count(gop) && gop != decoding_;
}

double RequestedGops::FetchWindowFilled() const {
  // The window ends at the stream's end (a loop's first GOP is the loop's
  // to ask for).
  const uint32_t window = std::min(fetch_ahead_, gops_ - 1 - std::min(shown_gop_, gops_ - 1));
  uint32_t in = 0;
  while (in < window) {
    const uint32_t g = shown_gop_ + in + 1;
    if (!held_.count(g) && !fetched_.count(g) && g != decoding_) break;
    ++in;
  }
  return window ? double(in) / window : 1.0;
}

bool RequestedGops::NextRequest(uint32_t* gop, GopRequest* request) {
  if (queue_.empty() || in_flight_.size() >= kFetchesInFlight) return false;
  if (!in_flight_.empty() && (in_flight_.count(wanted_) || queue_.front().gop == wanted_)) {
    return false;
  }
  *gop = queue_.front().gop;
  *request = queue_.front().request;
  queue_.pop_front();
  in_flight_[*gop] = *request;
  return true;
}

void RequestedGops::Fetched(uint32_t gop) {
  auto it = in_flight_.find(gop);
  if (it == in_flight_.end()) return;
  fetched_[gop] = it->second;
  in_flight_.erase(it);
}

bool RequestedGops::NextDecode(uint32_t* gop, GopRequest* request) {
  if (decoding_ != UINT32_MAX || fetched_.empty()) return false;
  // The GOP waited for first, else the nearest ahead of the one shown.
  auto next = fetched_.find(wanted_);
  if (next == fetched_.end()) {
    next = std::min_element(fetched_.begin(), fetched_.end(), [this](const auto& a, const auto& b) {
      return Ahead(a.first) < Ahead(b.first);
    });
    if (Ahead(next->first) > kAhead || !taken_) return false;
  }
  *gop = next->first;
  *request = next->second;
  // Fetched for more cameras than the loop wants now (decoding fewer keeps
  // up): those of them it wants. The time the loop gives a decode now.
  const uint64_t wanted = last_.budget.camera_mask, fetched = request->budget.camera_mask;
  const auto count = [](uint64_t mask) { return mask ? std::bitset<64>(mask).count() : 64; };
  if (wanted != 0 && count(fetched) > count(wanted) && (fetched == 0 || (fetched & wanted) != 0)) {
    request->budget.camera_mask = fetched == 0 ? wanted : fetched & wanted;
  }
  decoding_cameras_ = request->budget.camera_mask;
  request->budget.max_ms_per_gop = last_.budget.max_ms_per_gop;
  request->budget.floor_share = last_.budget.floor_share;
  decoding_ = *gop;
  fetched_.erase(next);
  return true;
}

void RequestedGops::Deliver(uint32_t gop, const fvv_decode_report& report, uint32_t cameras) {
  if (cameras == 0 && gop == decoding_)
    cameras = static_cast<uint32_t>(std::bitset<64>(decoding_cameras_).count());
  held_[gop] = {report, cameras};
  if (gop == decoding_) decoding_ = UINT32_MAX;
  in_flight_.erase(gop);
  fetched_.erase(gop);
  // The network stays busy: the next GOP, while it is within reach of the one shown.
  if (gop + 1 < gops_ && Ahead(gop + 1) <= fetch_ahead_) Ask(gop + 1, last_, false);
}

void RequestedGops::Retarget(const GopRequest& request) {
  last_ = request;
  for (Pending& p : queue_) p.request = request;
}

void RequestedGops::Failed(uint32_t gop) {
  in_flight_.erase(gop);
  if (gop == decoding_) decoding_ = UINT32_MAX;
  fetched_.erase(gop);
}

void RequestedGops::Forget(uint32_t gop) { held_.erase(gop); }

}  // namespace fvv
