// A frame source fed from outside the loop: the loop's asks become requests
// that the embedding serves in two steps, each one GOP at a time: fetch the
// GOP's fragments as far as the request's bytes allow (NextRequest, Fetched),
// then decode them under the loop's budget (NextDecode, Deliver). The web
// player drives it from JavaScript (player/web/module.cc); the decoded pixels
// stay with the embedding, the loop needs only the reports.
//
// Fetching runs further ahead of the playhead than decoding: bytes are small
// and absorb the network's swings, decoded frames are large. Fetches go up to
// `fetch_ahead` GOPs past the one shown, decodes kAhead, so the network is
// never idle while playback could use what it brings.
#ifndef FVV_PLAYER_PLAYBACK_REQUESTED_GOPS_H_
#define FVV_PLAYER_PLAYBACK_REQUESTED_GOPS_H_

#include <cstdint>
#include <deque>
#include <map>

#include "player/playback/frame_source.h"

namespace fvv {

class RequestedGops : public FrameSource {
 public:
  // GOPs decoded ahead of the one shown.
  static constexpr uint32_t kAhead = 2;
  // The play time fetched ahead of the GOP shown, at most: bytes enough to
  // ride out a network's swing of that long.
  static constexpr double kFetchAheadSeconds = 2.0;
  static uint32_t FetchAheadFor(double fps, uint32_t gop_frames) {
    return gop_frames ? uint32_t(kFetchAheadSeconds * fps / gop_frames + 0.999) : kAhead;
  }

  // Fetches under way at once, at most: a second one's request and first
  // bytes overlap the first's last bytes, so the link does not idle for a
  // round trip between GOPs.
  static constexpr uint32_t kFetchesInFlight = 2;

  // fetch_ahead: GOPs fetched ahead of the one shown (at least kAhead).
  RequestedGops(uint32_t frame_count, uint32_t gop_frames, uint32_t fetch_ahead = kAhead);

  bool Ready(uint32_t frame, const GopRequest& request) override;
  void Prefetch(uint32_t frame, const GopRequest& request) override;
  StatusOr<bool> Take(uint32_t frame, const GopRequest& request,
                      fvv_decode_report* report) override;
  bool Arriving(uint32_t frame) const override;
  double FetchWindowFilled() const override;
  uint32_t CamerasTaken() const override { return cameras_taken_; }
  void Retarget(const GopRequest& request) override;

  // The next request to serve, taken off the queue (it is then being
  // fetched); false when there is none or kFetchesInFlight are under way. A
  // second fetch starts beside the first only while the playhead waits for
  // neither: the GOP waited for has the link to itself.
  bool NextRequest(uint32_t* gop, GopRequest* request);
  // The GOP's bytes are in: the next request may be fetched.
  void Fetched(uint32_t gop);
  // The next fetched GOP to decode (it is then decoding), with its request:
  // the cameras it was fetched for (where they are more than the loop's
  // latest request wants, those of them it wants) and the loop's latest
  // time budget. Only within kAhead of the GOP shown, or the one the
  // playhead waits for (before the first frame is taken, only that one: what
  // its decode measured sets the cameras of the next); false when none is
  // due or one is decoding already.
  bool NextDecode(uint32_t* gop, GopRequest* request);
  // The GOP arrived, decoded (of `cameras`; 0: as many as its decode was
  // asked for): the loop can take its frames.
  void Deliver(uint32_t gop, const fvv_decode_report& report, uint32_t cameras = 0);
  // The GOP could not be served: it is asked for again when needed.
  void Failed(uint32_t gop);
  // The embedding dropped a GOP's frames (its cache is full).
  void Forget(uint32_t gop);
  bool Held(uint32_t gop) const { return held_.count(gop) != 0; }
  // Every request dropped (a seek): what was delivered stays.
  void ClearRequests() { queue_.clear(); }

 private:
  struct Pending {
    uint32_t gop;
    GopRequest request;
  };
  // Queues `gop` (at the front when urgent) unless held, in flight or queued.
  void Ask(uint32_t gop, const GopRequest& request, bool urgent);
  // GOPs past the one shown, in playing order (round the end).
  uint32_t Ahead(uint32_t gop) const { return (gop + gops_ - shown_gop_) % gops_; }
  uint32_t gops_;
  uint32_t gop_frames_;
  uint32_t fetch_ahead_;
  std::deque<Pending> queue_;
  struct HeldGop {
    fvv_decode_report report;
    uint32_t cameras;
  };
  std::map<uint32_t, HeldGop> held_;
  std::map<uint32_t, GopRequest> in_flight_;  // being fetched
  std::map<uint32_t, GopRequest> fetched_;    // fetched, not decoding yet
  uint32_t decoding_ = UINT32_MAX;            // being decoded
  uint64_t decoding_cameras_ = 0;             // its decode's camera mask
  uint32_t wanted_ = UINT32_MAX;              // the GOP the playhead waits for
  uint32_t shown_gop_ = 0;
  GopRequest last_{};  // the request of the GOP shown: the one the GOPs ahead take
  uint32_t cameras_taken_ = 0;
  bool taken_ = false;  // a frame was taken
};

}  // namespace fvv

#endif  // FVV_PLAYER_PLAYBACK_REQUESTED_GOPS_H_
