#include "encoder/encode/ordered_queue.h"

#include <algorithm>
#include <utility>

namespace fvv {

OrderedQueue::OrderedQueue(size_t max_pending)
    : max_pending_(std::max<size_t>(1, max_pending)), thread_([this] { Loop(); }) {}

OrderedQueue::~OrderedQueue() {
  {
    std::lock_guard<std::mutex> lock(mu_);
    stop_ = true;
    pending_.clear();
  }
  changed_.notify_all();
  thread_.join();
}

Status OrderedQueue::Push(std::function<Status()> task) {
  std::unique_lock<std::mutex> lock(mu_);
  changed_.wait(lock, [&] { return !error_.ok() || pending_.size() < max_pending_; });
  if (!error_.ok()) return error_;
  pending_.push_back(std::move(task));
  changed_.notify_all();
  return Status::Ok();
}

Status OrderedQueue::Finish() {
  std::unique_lock<std::mutex> lock(mu_);
  changed_.wait(lock, [&] { return pending_.empty() && !running_; });
  return error_;
}

void OrderedQueue::Loop() {
  std::unique_lock<std::mutex> lock(mu_);
  for (;;) {
    changed_.wait(lock, [&] { return stop_ || !pending_.empty(); });
    if (stop_) return;
    std::function<Status()> task = std::move(pending_.front());
    pending_.pop_front();
    running_ = true;
    lock.unlock();
    Status s = task();
    lock.lock();
    running_ = false;
    if (!s.ok() && error_.ok()) {
      error_ = std::move(s);
      pending_.clear();  // later tasks build on this one: none of them runs
    }
    changed_.notify_all();
  }
}

}  // namespace fvv
