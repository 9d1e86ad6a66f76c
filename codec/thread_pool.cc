#include "codec/thread_pool.h"

namespace fvv {
namespace {
thread_local bool in_pool_task = false;
}  // namespace

ThreadPool::ThreadPool(unsigned threads) {
  if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
  for (unsigned i = 1; i < threads; ++i) workers_.emplace_back([this] { WorkerLoop(); });
}

ThreadPool::~ThreadPool() {
  {
    std::lock_guard<std::mutex> lock(mu_);
    stop_ = true;
  }
  wake_.notify_all();
  for (auto& t : workers_) t.join();
}

void ThreadPool::Drain(Job* job) {
  const bool was_in_task = in_pool_task;
  in_pool_task = true;
  for (uint32_t i; (i = job->next.fetch_add(1)) < job->count;) {
    (*job->task)(i);
    job->done.fetch_add(1);
  }
  in_pool_task = was_in_task;
}

void ThreadPool::Run(uint32_t count, const std::function<void(uint32_t)>& task) {
  if (count == 0) return;
  if (workers_.empty() || count == 1 || in_pool_task) {
    for (uint32_t i = 0; i < count; ++i) task(i);
    return;
  }
  std::lock_guard<std::mutex> run_lock(run_mu_);
  Job job;
  job.task = &task;
  job.count = count;
  {
    std::lock_guard<std::mutex> lock(mu_);
    job_ = &job;
    ++generation_;
  }
  wake_.notify_all();
  Drain(&job);
  std::unique_lock<std::mutex> lock(mu_);
  finished_.wait(lock, [&] { return job.done.load() == job.count && job.workers_inside == 0; });
  job_ = nullptr;
}

void ThreadPool::WorkerLoop() {
  uint64_t seen = 0;
  for (;;) {
    Job* job;
    {
      std::unique_lock<std::mutex> lock(mu_);
      wake_.wait(lock, [&] { return stop_ || (job_ != nullptr && generation_ != seen); });
      if (stop_) return;
      seen = generation_;
      job = job_;
      ++job->workers_inside;
    }
    Drain(job);
    std::lock_guard<std::mutex> lock(mu_);
    --job->workers_inside;
    finished_.notify_all();
  }
}

}  // namespace fvv
