// Where the playback loop gets its frames: a decoder it drives itself (the
// native players), or GOPs that something outside fetches and decodes on the
// loop's requests (the web player, whose network and decoder are
// asynchronous). The loop's policy is the same over both.
#ifndef FVV_PLAYER_PLAYBACK_FRAME_SOURCE_H_
#define FVV_PLAYER_PLAYBACK_FRAME_SOURCE_H_

#include <cstdint>

#include "codec/base/status.h"
#include "fvv/fvv_decoder.hpp"

namespace fvv {

// What the loop asks of a GOP: the decode's budget (cameras, time, floor)
// and, for a source that fetches, the bytes its fetch may take.
struct GopRequest {
  fvv_decode_budget budget{};
  uint64_t fetch_bytes = 0;  // 0: no bandwidth measured yet (whole fragments)
};

class FrameSource {
 public:
  virtual ~FrameSource() = default;
  // Whether `frame` can be taken now without waiting for its GOP.
  virtual bool Ready(uint32_t frame, const GopRequest& request) = 0;
  // Asks for the GOP of `frame` ahead of need; returns at once.
  virtual void Prefetch(uint32_t frame, const GopRequest& request) = 0;
  // Makes `frame` the current one and gives its GOP's decode report. A source
  // that decodes waits for it; one fed from outside answers false when the
  // GOP is not there yet (and asks for it).
  virtual StatusOr<bool> Take(uint32_t frame, const GopRequest& request,
                              fvv_decode_report* report) = 0;
  // The loop's request changed since the last Take (fewer cameras keep up):
  // what is asked for and not yet started takes it.
  virtual void Retarget(const GopRequest& request) {}
  // How many cameras the GOP of the frame last taken decoded (0: not known).
  virtual uint32_t CamerasTaken() const { return 0; }
  // Whether the frame's GOP is still on its way (not all fetched): a wait for
  // it is then the network's, not the decoder's. A decoding source has it all.
  virtual bool Arriving(uint32_t frame) const { return false; }
  // For a source that fetches ahead: of the GOPs it fetches ahead of the one
  // shown, the share whose bytes are in (0 for a source that does not fetch).
  virtual double FetchWindowFilled() const { return 0; }
};

// The native source: a decoder that decodes ahead by itself.
class DecoderFrameSource : public FrameSource {
 public:
  explicit DecoderFrameSource(fvv_decoder* decoder) : dec_(decoder) {}
  bool Ready(uint32_t frame, const GopRequest& request) override;
  void Prefetch(uint32_t frame, const GopRequest& request) override;
  StatusOr<bool> Take(uint32_t frame, const GopRequest& request,
                      fvv_decode_report* report) override;
  uint32_t CamerasTaken() const override;
  // The frame last taken (null before any).
  const fvv_frame* frame() const { return frame_.get(); }

 private:
  fvv_decoder* dec_;
  FramePtr frame_;
};

}  // namespace fvv

#endif  // FVV_PLAYER_PLAYBACK_FRAME_SOURCE_H_
