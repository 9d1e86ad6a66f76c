// A fixed pool of worker threads that implements ParallelRunner. The calling
// thread takes part in the work, and a call made from inside a task runs inline,
// so nested parallel sections cannot deadlock.
#ifndef FVV_CODEC_THREAD_POOL_H_
#define FVV_CODEC_THREAD_POOL_H_

#include <atomic>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

#include "codec/parallel.h"

namespace fvv {

class ThreadPool {
 public:
  // threads = 0: one per hardware thread. threads = 1: no worker threads.
  explicit ThreadPool(unsigned threads = 0);
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  unsigned size() const { return static_cast<unsigned>(workers_.size()) + 1; }
  void Run(uint32_t count, const std::function<void(uint32_t)>& task);
  ParallelRunner runner() {
    return [this](uint32_t count, const std::function<void(uint32_t)>& task) { Run(count, task); };
  }

 private:
  struct Job {
    const std::function<void(uint32_t)>* task = nullptr;
    uint32_t count = 0;
    std::atomic<uint32_t> next{0};
    std::atomic<uint32_t> done{0};
    int workers_inside = 0;  // guarded by mu_: the job outlives every worker using it
  };
  void WorkerLoop();
  static void Drain(Job* job);

  std::vector<std::thread> workers_;
  std::mutex mu_;
  std::condition_variable wake_;
  std::condition_variable finished_;
  Job* job_ = nullptr;
  uint64_t generation_ = 0;
  bool stop_ = false;
  std::mutex run_mu_;  // one top-level job at a time
};

}  // namespace fvv

#endif  // FVV_CODEC_THREAD_POOL_H_
