// Real-time playback of a stream, shared by `fvv play`'s window and the headless
// benchmarks: the playhead on the wall clock, the GOP time budgets from the
// PlaybackController, the cameras the view blends, the wait when a GOP is not
// decoded in time (playback slows instead of skipping), and what it measured.
// It draws nothing: the caller renders the frame the source holds. Its frames
// come from a FrameSource: a decoder it drives (native players) or GOPs an
// embedding fetches and decodes on its requests (the web player), which then
// also reports what its fetches measured, for the bytes the next GOP may take.
#ifndef FVV_PLAYER_PLAYBACK_PLAYBACK_LOOP_H_
#define FVV_PLAYER_PLAYBACK_PLAYBACK_LOOP_H_

#include <glm/glm.hpp>
#include <vector>

#include "codec/base/status.h"
#include "fvv/fvv_decoder.hpp"
#include "player/playback/fetch_plan.h"
#include "player/playback/frame_source.h"
#include "player/playback/playback_controller.h"

namespace fvv {

struct Transport {
  double playhead = 0;  // in frames
  bool playing = true, loop = true;
  double speed = 1;
};

// Totals since the loop started.
struct PlaybackStats {
  uint64_t frames_drawn = 0;
  uint64_t frames_advanced = 0;  // content frames the playhead moved forward over
  uint64_t gops = 0;
  uint64_t bytes_decoded = 0, bytes_available = 0;
  uint64_t frames_without_texture = 0;  // shown with no texture byte decoded
  uint64_t stalls = 0;                  // frames on screen for more than 2 frame times
  // Times the playhead was held for a GOP not there yet, after the first frame
  // (a stall the source caused, where `stalls` also counts a slow display).
  uint64_t waits = 0;
  uint64_t bytes_fetched = 0;  // as the embedding reported its fetches
  double decode_ms = 0;
};

class PlaybackLoop {
 public:
  // `source` outlives the loop.
  PlaybackLoop(FrameSource* source, const fvv_stream_info& info, std::vector<glm::vec3> centres,
               double floor_share = PlaybackController::kDefaultFloorShare);

  // Moves the playhead on by dt seconds of wall time and takes the frame to
  // show from the source: a new one when its GOP is decoded, else the one
  // shown (the playhead waits). The first frame is waited for: a decoding
  // source decodes it whatever it takes; until one fed from outside has it,
  // has_frame() stays false. eye and target are the view's last, for the
  // cameras the next GOP decodes.
  Status Advance(double dt, const glm::vec3& eye, const glm::vec3& target);
  bool has_frame() const { return shown_ != UINT32_MAX; }
  // Whether the frame shown differs from the one before the last Advance.
  bool frame_changed() const { return changed_; }
  uint32_t frame_index() const { return shown_; }
  // A fetch the embedding made for a GOP: `bytes` in `seconds` (request to
  // last byte). The bandwidth it measures sizes each GOP's fetch_bytes.
  void FetchMeasured(uint64_t bytes, double seconds);
  double bytes_per_second() const { return bandwidth_.bytes_per_second(); }
  // What the next GOP's fetch may take: a share of what the bandwidth brings
  // while a GOP plays, lower at the start and after a GOP came late (0 until
  // a fetch was measured: whole fragments).
  uint64_t FetchBudget() const;
  // Moves the playhead to `frame` (a seek or a step): shown once its GOP is there.
  void Seek(uint32_t frame);
  // After the caller has drawn the frame: its upload and draw time.
  void FrameDrawn(double draw_ms);

  Transport& transport() { return transport_; }
  const Transport& transport() const { return transport_; }
  bool all_cameras = false;  // decode every camera, not only those the view blends
  // After the first frame of a start or a seek the playhead holds, the frame
  // on screen, until the GOP after it is ready too, at most kMaxPrerollS: that
  // GOP decodes while the first frames are drawn (when a software rasteriser
  // compiles its pipelines) and would otherwise come late, a wait just after
  // the start. Not counted as a wait or a stall: it is the start-up's.
  static constexpr double kMaxPrerollS = 1.0;
  bool prerolling() const { return preroll_s_ >= 0; }
  const PlaybackController& controller() const { return control_; }
  const PlaybackStats& stats() const { return stats_; }
  // The last GOP's decode report, for the HUD.
  const fvv_decode_report& report() const;

 private:
  GopRequest Request() const;
  // The cameras to decode for the view (eye, target), reaching further round
  // the actor while the view turns.
  uint64_t ViewMask(const glm::vec3& eye, const glm::vec3& target);
  uint32_t LastGop() const;
  // Looping: asks for the first GOP ahead (once per pass).
  void PrefetchFirstGop(const glm::vec3& eye, const glm::vec3& target);

  FrameSource* source_;
  fvv_stream_info info_;
  std::vector<glm::vec3> centres_;
  double fps_;
  Transport transport_;
  PlaybackController control_;
  PlaybackStats stats_;
  BandwidthEstimate bandwidth_;
  // The share of what the bandwidth brings in a GOP's play time that its
  // fetch may take (FetchBudget): low at the start, so that GOPs come ahead of
  // the playhead, then up to kSteadyFetchShare while none is late, down after
  // a wait. Past it as the fetch window fills beyond half, up to
  // kMaxFetchShare with the window full: fetches that are ahead take more
  // until they bring what the link does (a measured rate undercounts it,
  // each request paying its round trip), and the network never idles while
  // the window has room.
  static constexpr double kSteadyFetchShare = 0.97, kMaxFetchShare = 1.2, kMinFetchShare = 0.4;
  double FetchShare() const;
  double fetch_share_ = 0.6;
  double fetch_filled_ = 0;     // the source's FetchWindowFilled, as of the last Advance
  bool fetch_late_ = false;     // the playhead waited for this GOP's bytes
  fvv_decode_report report_{};  // of the frame shown
  uint32_t shown_ = UINT32_MAX, last_gop_ = UINT32_MAX;
  uint32_t mask_gop_ = UINT32_MAX;
  uint64_t gop_mask_ = 0;
  uint64_t wrap_mask_ = 0;  // the cameras of the first GOP, decoded ahead of a loop
  bool wrap_mask_set_ = false;
  bool wrap_asked_ = false;
  glm::vec3 last_direction_{0.0f};  // from the actor to the eye, when cameras were last picked
  bool changed_ = false;
  bool waiting_ = true;      // the playhead is held at the frame it wants (the first, at first)
  bool preroll_due_ = true;  // the next frame taken starts a preroll (a start, a seek)
  double preroll_s_ = -1;    // how long the preroll has held the playhead; < 0: none
  double frame_ms_ = 0;      // smoothed upload + draw time
  double wait_ms_ = 0;       // the playhead's wait for the GOP being waited for
  double on_screen_s_ = 0;   // how long the shown frame has been on screen
};

}  // namespace fvv

#endif  // FVV_PLAYER_PLAYBACK_PLAYBACK_LOOP_H_
