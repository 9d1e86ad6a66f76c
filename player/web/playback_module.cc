// The playback loop (player/playback/playback_loop.h) in the WebAssembly
// module: the page's loop is this one, over GOPs the page fetches and decodes
// in its worker as the loop asks (player/playback/requested_gops.h). The
// JavaScript over it is player/web/fvv_playback.mjs.
#include <emscripten.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <vector>

#include "container/geometric_visibility.h"
#include "player/playback/depth_map_triangles.h"
#include "player/playback/playback_loop.h"
#include "player/playback/requested_gops.h"
#include "player/playback/view_cameras.h"

namespace {

struct WebPlayback {
  WebPlayback(const fvv_stream_info& info, std::vector<glm::vec3> centres, double floor_share)
      : gops(info.frame_count, info.gop_frames,
             fvv::RequestedGops::FetchAheadFor(double(info.frame_rate_num) / info.frame_rate_den,
                                               info.gop_frames)),
        loop(&gops, info, std::move(centres), floor_share) {}
  fvv::RequestedGops gops;
  fvv::PlaybackLoop loop;
};

std::vector<glm::vec3> Centres(const float* xyz, uint32_t count) {
  std::vector<glm::vec3> centres;
  for (uint32_t c = 0; c < count; ++c)
    centres.emplace_back(xyz[3 * c], xyz[3 * c + 1], xyz[3 * c + 2]);
  return centres;
}

// A GOP request as fvv_playback.mjs reads it: 6 doubles.
void WriteRequest(uint32_t gop, const fvv::GopRequest& r, double* out) {
  out[0] = gop;
  out[1] = double(uint32_t(r.budget.camera_mask));
  out[2] = double(uint32_t(r.budget.camera_mask >> 32));
  out[3] = r.budget.max_ms_per_gop;
  out[4] = r.budget.floor_share;
  out[5] = double(r.fetch_bytes);
}

}  // namespace

extern "C" {

// A loop over a stream of `frame_count` frames at num/den fps in GOPs of
// `gop_frames`, with the cameras' centres (x, y, z each); null when the
// stream's numbers cannot play.
EMSCRIPTEN_KEEPALIVE WebPlayback* fvv_web_playback_create(uint32_t frame_count, uint32_t fps_num,
                                                          uint32_t fps_den, uint32_t gop_frames,
                                                          const float* centres,
                                                          uint32_t camera_count,
                                                          double floor_share) {
  if (frame_count == 0 || fps_num == 0 || fps_den == 0 || gop_frames == 0 || camera_count == 0 ||
      camera_count > 64) {
    return nullptr;
  }
  fvv_stream_info info{};
  info.frame_count = frame_count;
  info.frame_rate_num = fps_num;
  info.frame_rate_den = fps_den;
  info.gop_frames = gop_frames;
  info.camera_count = camera_count;
  return new WebPlayback(
      info, Centres(centres, camera_count),
      floor_share > 0 ? floor_share : fvv::PlaybackController::kDefaultFloorShare);
}

EMSCRIPTEN_KEEPALIVE void fvv_web_playback_destroy(WebPlayback* p) { delete p; }

// One tick of the page's clock: dt seconds, the view's eye and target.
// 0, or 1 when the source failed (it cannot: the page's source holds reports).
EMSCRIPTEN_KEEPALIVE int fvv_web_playback_advance(WebPlayback* p, double dt, float ex, float ey,
                                                  float ez, float tx, float ty, float tz) {
  return p->loop.Advance(dt, {ex, ey, ez}, {tx, ty, tz}).ok() ? 0 : 1;
}

// The loop's state after a tick, as 26 doubles (fvv_playback.mjs names them).
EMSCRIPTEN_KEEPALIVE void fvv_web_playback_state(const WebPlayback* p, double* out) {
  const fvv::PlaybackLoop& l = p->loop;
  const fvv::PlaybackStats& s = l.stats();
  const fvv_decode_report& r = l.report();
  const fvv::Transport& t = l.transport();
  const double v[] = {double(l.has_frame()),
                      l.has_frame() ? double(l.frame_index()) : -1.0,
                      double(l.frame_changed()),
                      t.playhead,
                      double(t.playing),
                      l.bytes_per_second(),
                      double(l.FetchBudget()),
                      double(s.stalls),
                      double(s.frames_without_texture),
                      double(s.gops),
                      double(s.bytes_fetched),
                      s.decode_ms,
                      l.controller().NextMaxMs(),
                      double(l.controller().below_real_time()),
                      double(s.frames_drawn),
                      double(s.frames_advanced),
                      double(s.bytes_decoded),
                      double(s.bytes_available),
                      double(r.bytes_decoded),
                      double(r.bytes_available),
                      r.decode_ms,
                      double(r.bitplanes[0]),
                      double(r.bitplanes[1]),
                      double(r.bitplanes[2]),
                      double(s.waits),
                      double(l.controller().max_cameras())};
  for (size_t i = 0; i < sizeof(v) / sizeof(v[0]); ++i) out[i] = v[i];
}

// The next GOP to fetch: 1 and out = {gop, camera mask low 32 bits, high 32
// bits, max ms, floor share, fetch bytes}; 0 when none is due.
EMSCRIPTEN_KEEPALIVE int fvv_web_playback_next_request(WebPlayback* p, double* out) {
  uint32_t gop;
  fvv::GopRequest r;
  if (!p->gops.NextRequest(&gop, &r)) return 0;
  WriteRequest(gop, r, out);
  return 1;
}

// The next fetched GOP to decode: 1 and out as fvv_web_playback_next_request's;
// 0 when none is due.
EMSCRIPTEN_KEEPALIVE int fvv_web_playback_next_decode(WebPlayback* p, double* out) {
  uint32_t gop;
  fvv::GopRequest r;
  if (!p->gops.NextDecode(&gop, &r)) return 0;
  WriteRequest(gop, r, out);
  return 1;
}

EMSCRIPTEN_KEEPALIVE void fvv_web_playback_deliver(WebPlayback* p, uint32_t gop,
                                                   double bytes_decoded, double bytes_available,
                                                   double decode_ms, double max_ms, int complete,
                                                   uint32_t luma_planes, uint32_t cb_planes,
                                                   uint32_t cr_planes, uint32_t cameras) {
  fvv_decode_report r{};
  r.bytes_decoded = uint64_t(bytes_decoded);
  r.bytes_available = uint64_t(bytes_available);
  r.decode_ms = decode_ms;
  r.max_ms_per_gop = max_ms;
  r.complete = complete;
  r.bitplanes[0] = luma_planes;
  r.bitplanes[1] = cb_planes;
  r.bitplanes[2] = cr_planes;
  p->gops.Deliver(gop, r, cameras);
}

EMSCRIPTEN_KEEPALIVE void fvv_web_playback_fetched(WebPlayback* p, uint32_t gop) {
  p->gops.Fetched(gop);
}
EMSCRIPTEN_KEEPALIVE void fvv_web_playback_failed(WebPlayback* p, uint32_t gop) {
  p->gops.Failed(gop);
}
EMSCRIPTEN_KEEPALIVE void fvv_web_playback_forget(WebPlayback* p, uint32_t gop) {
  p->gops.Forget(gop);
}
EMSCRIPTEN_KEEPALIVE int fvv_web_playback_held(const WebPlayback* p, uint32_t gop) {
  return p->gops.Held(gop);
}
EMSCRIPTEN_KEEPALIVE void fvv_web_playback_fetch_measured(WebPlayback* p, double bytes,
                                                          double seconds) {
  p->loop.FetchMeasured(uint64_t(bytes), seconds);
}
EMSCRIPTEN_KEEPALIVE void fvv_web_playback_frame_drawn(WebPlayback* p, double ms) {
  p->loop.FrameDrawn(ms);
}
EMSCRIPTEN_KEEPALIVE void fvv_web_playback_seek(WebPlayback* p, uint32_t frame) {
  p->gops.ClearRequests();
  p->loop.Seek(frame);
}
// playing, looping (0 or 1), speed (> 0).
EMSCRIPTEN_KEEPALIVE void fvv_web_playback_set_transport(WebPlayback* p, int playing, int loop,
                                                         double speed) {
  fvv::Transport& t = p->loop.transport();
  t.playing = playing != 0;
  t.loop = loop != 0;
  if (speed > 0) t.speed = speed;
}

// The cameras a view blends (fvv::ViewCameras, as the native renderer picks
// them: within 110 degrees, at least 3), among `count` centres, as a mask in
// two 32-bit halves (out[0] low, out[1] high).
EMSCRIPTEN_KEEPALIVE void fvv_web_view_cameras(const float* centres, uint32_t count, float ex,
                                               float ey, float ez, float tx, float ty, float tz,
                                               uint32_t* out) {
  const uint64_t mask =
      fvv::ViewCameras(Centres(centres, count), {ex, ey, ez}, {tx, ty, tz}, 110.0f, 3);
  out[0] = uint32_t(mask);
  out[1] = uint32_t(mask >> 32);
}

// The renderer's constants (container/geometric_visibility.h), for the
// page's shaders: depth tolerance, slope texels, min facing, full facing,
// angle epsilon, view exponent, facing exponent.
EMSCRIPTEN_KEEPALIVE void fvv_web_render_constants(double* out) {
  namespace gv = fvv::geometric_visibility;
  const double v[] = {gv::kDepthTolerance, gv::kSlopeTexels,  gv::kMinFacing,     gv::kFullFacing,
                      gv::kAngleEpsilon,   gv::kViewExponent, gv::kFacingExponent};
  for (size_t i = 0; i < sizeof(v) / sizeof(v[0]); ++i) out[i] = v[i];
}

// The size of a camera's depth map (geometric_visibility::DepthMapSize).
EMSCRIPTEN_KEEPALIVE void fvv_web_depth_map_size(uint32_t width, uint32_t height, int32_t* out) {
  fvv::geometric_visibility::DepthMapSize(width, height, &out[0], &out[1]);
}

// The triangles the depth maps draw (player/playback/depth_map_triangles.h),
// written to `out` (room for triangle_count * 3); returns how many indices.
EMSCRIPTEN_KEEPALIVE uint32_t fvv_web_depth_map_triangles(const float* positions,
                                                          uint32_t vertex_count,
                                                          const uint32_t* triangles,
                                                          uint32_t triangle_count, uint32_t* out) {
  const std::vector<uint32_t> kept =
      fvv::DepthMapTriangles(positions, vertex_count, triangles, triangle_count);
  std::copy(kept.begin(), kept.end(), out);
  return uint32_t(kept.size());
}

}  // extern "C"
