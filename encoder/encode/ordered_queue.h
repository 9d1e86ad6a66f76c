// One background thread that runs tasks in the order they were queued: the
// encoder hands it each tracked frame's resampling and coding, so that work
// runs beside the tracking of the next frames (tracking is sequential: each
// frame starts from the last one's pose). The queue is bounded, so a producer
// faster than the consumer waits rather than holding every frame in memory.
#ifndef FVV_ENCODER_ENCODE_ORDERED_QUEUE_H_
#define FVV_ENCODER_ENCODE_ORDERED_QUEUE_H_

#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>

#include "codec/base/status.h"

namespace fvv {

class OrderedQueue {
 public:
  // At most max_pending tasks wait (>= 1); one more may be running.
  explicit OrderedQueue(size_t max_pending);
  // Discards the tasks still waiting and joins the thread after the one
  // running, if any, returns.
  ~OrderedQueue();
  OrderedQueue(const OrderedQueue&) = delete;
  OrderedQueue& operator=(const OrderedQueue&) = delete;

  // Queues a task, waiting while the queue is full. Once a task has failed,
  // nothing more is queued or run: Push returns that first error.
  Status Push(std::function<Status()> task);
  // Waits until every queued task has run; the first error, or Ok.
  Status Finish();

 private:
  void Loop();

  const size_t max_pending_;
  std::mutex mu_;
  std::condition_variable changed_;
  std::deque<std::function<Status()>> pending_;
  bool running_ = false;  // a task is under way
  bool stop_ = false;
  Status error_;
  std::thread thread_;
};

}  // namespace fvv

#endif  // FVV_ENCODER_ENCODE_ORDERED_QUEUE_H_
