// How codec work is spread over threads. The codec library starts no threads of
// its own (it is embedded in players that own their threading); callers pass a
// runner. SerialRunner runs inline; fvv_thread_pool provides a pooled one.
#ifndef FVV_CODEC_BASE_PARALLEL_H_
#define FVV_CODEC_BASE_PARALLEL_H_

#include <cstdint>
#include <functional>

namespace fvv {

// Runs task(i) for every i in [0, count), possibly concurrently, and returns when
// all have finished. Tasks must not depend on each other's order.
using ParallelRunner =
    std::function<void(uint32_t count, const std::function<void(uint32_t)>& task)>;

inline void SerialRunner(uint32_t count, const std::function<void(uint32_t)>& task) {
  for (uint32_t i = 0; i < count; ++i) task(i);
}

}  // namespace fvv

#endif  // FVV_CODEC_BASE_PARALLEL_H_
