// A fixed pool of worker threads that implements ParallelRunner. The calling
// thread takes part in its own job, and idle workers join any job posted, a
// nested one (Run called from inside a task) included, newest first: a task
// that ends early and opens a parallel section of its own (a channel whose
// SPIHT decode is done starting its inverse transform) gets the threads that
// have nothing else to do. A caller waiting for its job's last tasks helps with
// the sections those tasks opened. No thread waits for a task nobody has
// started (each caller works through its own job's tasks before it waits), so
// nesting cannot deadlock.
#ifndef FVV_CODEC_BASE_THREAD_POOL_H_
#define FVV_CODEC_BASE_THREAD_POOL_H_

#include <atomic>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

#include "codec/base/parallel.h"

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
    int workers_inside = 0;       // guarded by mu_: the job outlives every worker using it
    const Job* parent = nullptr;  // the job whose task called Run, if any
  };
  void WorkerLoop();
  static void Drain(Job* job);
  // The newest posted job with a task nobody has taken, or null; with `under`,
  // only jobs opened by its tasks or theirs. Needs mu_.
  Job* OpenJob(const Job* under) const;

  std::vector<std::thread> workers_;
  std::mutex mu_;
  std::condition_variable wake_;
  std::condition_variable finished_;
  std::vector<Job*> jobs_;  // guarded by mu_: posted and not yet returned from Run
  bool stop_ = false;
};

}  // namespace fvv

#endif  // FVV_CODEC_BASE_THREAD_POOL_H_
