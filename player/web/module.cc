// The WebAssembly module of the decoder library: the C API of
// include/fvv/fvv_decoder.h, and the player's fetch policy
// (player/playback/fetch_plan.h) compiled in so that the page runs the same
// code as any native streaming player (player/web/CMakeLists.txt exports the
// functions; player/web/fvv_decoder_api.mjs is the JavaScript over them).
#include <emscripten.h>

#include <cstddef>
#include <cstdint>
#include <vector>

#include "fvv/fvv_decoder.h"
#include "player/playback/fetch_plan.h"

// fvv_decoder_api.mjs reads and writes the C API's structs at these offsets
// (wasm32); a change to a struct fails the build here, not the page.
static_assert(sizeof(void*) == 4 && sizeof(size_t) == 4, "a wasm32 build");
static_assert(sizeof(fvv_decoder_settings) == 40 &&
                  offsetof(fvv_decoder_settings, decode_ahead) == 16 &&
                  offsetof(fvv_decoder_settings, max_gop_samples) == 24 &&
                  offsetof(fvv_decoder_settings, max_fragment_bytes) == 32,
              "fvv_decoder_settings");
static_assert(sizeof(fvv_stream_info) == 60, "fvv_stream_info: 15 u32");
static_assert(sizeof(fvv_fragment_info) == 56 && offsetof(fvv_fragment_info, offset) == 16 &&
                  offsetof(fvv_fragment_info, head_size) == 32 &&
                  offsetof(fvv_fragment_info, surface_size) == 48,
              "fvv_fragment_info");
static_assert(sizeof(fvv_decode_budget) == 40 && offsetof(fvv_decode_budget, format) == 16 &&
                  offsetof(fvv_decode_budget, camera_mask) == 24 &&
                  offsetof(fvv_decode_budget, floor_share) == 32,
              "fvv_decode_budget");
static_assert(sizeof(fvv_frame) == 104 && offsetof(fvv_frame, views) == 32 &&
                  offsetof(fvv_frame, report) == 40 && offsetof(fvv_frame, surface) == 96,
              "fvv_frame");
static_assert(offsetof(fvv_decode_report, bitplanes) == 16 &&
                  offsetof(fvv_decode_report, decode_ms) == 32 &&
                  offsetof(fvv_decode_report, complete) == 40 &&
                  offsetof(fvv_decode_report, max_ms_per_gop) == 48,
              "fvv_decode_report");
static_assert(sizeof(fvv_view) == 8, "fvv_view");
static_assert(sizeof(fvv_model) == 44 && offsetof(fvv_model, triangles) == 40, "fvv_model");
static_assert(sizeof(fvv_camera) == 208 && offsetof(fvv_camera, fx) == 16 &&
                  offsetof(fvv_camera, rotation) == 88 && offsetof(fvv_camera, centre) == 184,
              "fvv_camera");

extern "C" {

// The prefix of each of `count` fragments (heads[i], sizes[i], surfaces[i])
// to fetch within `budget` bytes, into prefixes[i] (fvv::PlanPrefixes).
EMSCRIPTEN_KEEPALIVE void fvv_web_plan_prefixes(const uint64_t* heads, const uint64_t* sizes,
                                                const uint64_t* surfaces, uint32_t count,
                                                uint64_t budget, uint64_t* prefixes) {
  std::vector<fvv::FragmentSizes> fragments(count);
  for (uint32_t i = 0; i < count; ++i) fragments[i] = {heads[i], sizes[i], surfaces[i]};
  const std::vector<uint64_t> plan = fvv::PlanPrefixes(fragments, budget);
  for (uint32_t i = 0; i < count; ++i) prefixes[i] = plan[i];
}

// The smoothed bandwidth after a fetch of `bytes` in `seconds`, from the
// estimate `rate` before it (fvv::BandwidthEstimate; 0 before any fetch).
EMSCRIPTEN_KEEPALIVE double fvv_web_bandwidth_after(double rate, uint64_t bytes, double seconds) {
  fvv::BandwidthEstimate b(rate);
  b.Measured(bytes, seconds);
  return b.bytes_per_second();
}

// The bytes a GOP's fetch may take (fvv::GopFetchBudget).
EMSCRIPTEN_KEEPALIVE uint64_t fvv_web_gop_fetch_budget(double bytes_per_second,
                                                       double gop_seconds) {
  return fvv::GopFetchBudget(bytes_per_second, gop_seconds);
}

}  // extern "C"
