// A frame source fed from outside the loop: the loop's asks become requests
// that the embedding serves (fetch the GOP's fragments as far as the request's
// bytes allow, decode them under its budget) and answers with Deliver. One GOP
// is fetched at a time; once its bytes are in (Fetched) the next fetch may
// start while it decodes, so the network does not wait for the decoder. The web player drives it from JavaScript (player/web/module.cc);
// the decoded pixels stay with the embedding, the loop needs only the reports.
//
// Fetching runs ahead of the playhead: each GOP delivered asks for the next,
// up to kAhead GOPs past the one shown, so the network is never idle while
// playback could use what it brings.
#ifndef FVV_PLAYER_PLAYBACK_REQUESTED_GOPS_H_
#define FVV_PLAYER_PLAYBACK_REQUESTED_GOPS_H_

#include <cstdint>
#include <deque>
#include <map>
#include <set>

#include "player/playback/frame_source.h"

namespace fvv {

class RequestedGops : public FrameSource {
 public:
  // GOPs fetched ahead of the one shown.
  static constexpr uint32_t kAhead = 2;

  RequestedGops(uint32_t frame_count, uint32_t gop_frames);

  bool Ready(uint32_t frame, const GopRequest& request) override;
  void Prefetch(uint32_t frame, const GopRequest& request) override;
  StatusOr<bool> Take(uint32_t frame, const GopRequest& request,
                      fvv_decode_report* report) override;

  // The next request to serve, taken off the queue (it is then being
  // fetched); false when there is none or a fetch is under way.
  bool NextRequest(uint32_t* gop, GopRequest* request);
  // The GOP's bytes are in: the next request may be fetched while it decodes.
  void Fetched(uint32_t gop);
  // The GOP arrived, decoded: the loop can take its frames.
  void Deliver(uint32_t gop, const fvv_decode_report& report);
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
  uint32_t gops_;
  uint32_t gop_frames_;
  std::deque<Pending> queue_;
  std::map<uint32_t, fvv_decode_report> held_;
  uint32_t in_flight_ = UINT32_MAX;  // being fetched
  std::set<uint32_t> decoding_;      // fetched, not yet delivered
  uint32_t shown_gop_ = 0;
  GopRequest last_{};  // the request of the GOP shown: the one the GOPs ahead take
};

}  // namespace fvv

#endif  // FVV_PLAYER_PLAYBACK_REQUESTED_GOPS_H_
