#include "codec/base/thread_pool.h"

#include <algorithm>

#include "codec/base/threads.h"

namespace fvv {
namespace {
// The job whose task this thread runs (the innermost, where tasks nest).
thread_local const void* current_job = nullptr;
}  // namespace

ThreadPool::ThreadPool(unsigned threads) {
  if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
  if (!kThreadsAvailable) threads = 1;  // the caller's thread runs every task
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
  const void* outer = current_job;
  current_job = job;
  for (uint32_t i; (i = job->next.fetch_add(1)) < job->count;) {
    (*job->task)(i);
    job->done.fetch_add(1);
  }
  current_job = outer;
}

ThreadPool::Job* ThreadPool::OpenJob(const Job* under) const {
  for (auto it = jobs_.rbegin(); it != jobs_.rend(); ++it) {
    Job* job = *it;
    if (job->next.load() >= job->count) continue;
    if (!under) return job;
    for (const Job* p = job->parent; p; p = p->parent)
      if (p == under) return job;
  }
  return nullptr;
}

void ThreadPool::Run(uint32_t count, const std::function<void(uint32_t)>& task) {
  if (count == 0) return;
  if (workers_.empty() || count == 1) {
    for (uint32_t i = 0; i < count; ++i) task(i);
    return;
  }
  Job job;
  job.task = &task;
  job.count = count;
  job.parent = static_cast<const Job*>(current_job);
  {
    std::lock_guard<std::mutex> lock(mu_);
    jobs_.push_back(&job);
  }
  wake_.notify_all();
  finished_.notify_all();  // callers waiting on an ancestor job help with this one
  Drain(&job);
  // While other threads finish this job's tasks, the caller helps with the
  // sections they open, and with no others: this thread may hold per-thread
  // buffers in use that an unrelated job's task would reuse, a hazard no
  // greater than running its own job's tasks.
  std::unique_lock<std::mutex> lock(mu_);
  jobs_.erase(std::find(jobs_.begin(), jobs_.end(), &job));
  while (job.done.load() != job.count || job.workers_inside != 0) {
    Job* nested = job.done.load() != job.count ? OpenJob(&job) : nullptr;
    if (!nested) {
      finished_.wait(lock);
      continue;
    }
    ++nested->workers_inside;
    lock.unlock();
    Drain(nested);
    lock.lock();
    --nested->workers_inside;
    finished_.notify_all();
  }
}

void ThreadPool::WorkerLoop() {
  for (;;) {
    Job* job = nullptr;
    {
      // One look per wake-up: other threads take tasks without the lock, so a
      // second look could find the job exhausted.
      std::unique_lock<std::mutex> lock(mu_);
      wake_.wait(lock, [&] { return stop_ || (job = OpenJob(nullptr)) != nullptr; });
      if (stop_) return;
      ++job->workers_inside;
    }
    Drain(job);
    std::lock_guard<std::mutex> lock(mu_);
    --job->workers_inside;
    finished_.notify_all();
  }
}

}  // namespace fvv
