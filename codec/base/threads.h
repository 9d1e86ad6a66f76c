// Whether this build can start threads. A WebAssembly build without pthreads
// (what a page that is not cross-origin isolated runs: no SharedArrayBuffer)
// cannot: there every parallel path of the decoder runs serially, and nothing
// is decoded in the background.
#ifndef FVV_CODEC_BASE_THREADS_H_
#define FVV_CODEC_BASE_THREADS_H_

namespace fvv {

#if defined(__EMSCRIPTEN__) && !defined(__EMSCRIPTEN_PTHREADS__)
constexpr bool kThreadsAvailable = false;
#else
constexpr bool kThreadsAvailable = true;
#endif

}  // namespace fvv

#endif  // FVV_CODEC_BASE_THREADS_H_
