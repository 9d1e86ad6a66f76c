// The encoder's background queue (encoder/encode/ordered_queue.h): tasks run
// in order, the first error stops the rest and reaches the producer, the
// queue bounds what waits, and destruction never runs what was discarded.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <future>
#include <thread>
#include <vector>

#include "encoder/encode/ordered_queue.h"

namespace fvv {
namespace {

TEST(OrderedQueue, RunsTasksInTheOrderQueued) {
  std::vector<int> ran;  // touched by the worker only, read after Finish
  OrderedQueue q(3);
  for (int i = 0; i < 500; ++i) {
    ASSERT_TRUE(q.Push([&ran, i] {
                   ran.push_back(i);
                   return Status::Ok();
                 }).ok());
  }
  ASSERT_TRUE(q.Finish().ok());
  ASSERT_EQ(ran.size(), 500u);
  for (int i = 0; i < 500; ++i) ASSERT_EQ(ran[i], i);
}

TEST(OrderedQueue, FirstErrorStopsLaterTasksAndReachesTheProducer) {
  std::atomic<int> ran{0}, after{0};
  OrderedQueue q(2);
  Status pushed;
  int i = 0;
  for (; i < 1000 && pushed.ok(); ++i) {
    pushed = q.Push([&, i] {
      if (i > 5) ++after;
      ++ran;
      return i == 5 ? InvalidArgument("frame 5 failed") : Status::Ok();
    });
  }
  EXPECT_FALSE(pushed.ok()) << "a Push after the failure must return it";
  EXPECT_EQ(pushed.message(), "frame 5 failed");
  const Status finished = q.Finish();
  EXPECT_EQ(finished.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(finished.message(), "frame 5 failed");
  EXPECT_EQ(after.load(), 0) << "tasks after the failed one build on it: none may run";
  EXPECT_EQ(ran.load(), 6);
}

TEST(OrderedQueue, ProducerWaitsWhileTheQueueIsFull) {
  std::promise<void> release;
  std::shared_future<void> gate = release.get_future().share();
  std::atomic<bool> started{false};
  OrderedQueue q(2);
  EXPECT_TRUE(q.Push([&] {
                 started = true;
                 gate.wait();
                 return Status::Ok();
               }).ok());
  while (!started) std::this_thread::yield();
  // The first task runs; two more may wait; the fourth Push must block.
  EXPECT_TRUE(q.Push([] { return Status::Ok(); }).ok());
  EXPECT_TRUE(q.Push([] { return Status::Ok(); }).ok());
  std::atomic<bool> fourth_returned{false};
  std::thread producer([&] {
    EXPECT_TRUE(q.Push([] { return Status::Ok(); }).ok());
    fourth_returned = true;
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT_FALSE(fourth_returned.load()) << "Push returned with the queue full";
  release.set_value();
  producer.join();
  EXPECT_TRUE(fourth_returned.load());
  EXPECT_TRUE(q.Finish().ok());
}

TEST(OrderedQueue, DestructionDiscardsWaitingTasks) {
  std::promise<void> release;
  std::shared_future<void> gate = release.get_future().share();
  std::atomic<bool> started{false};
  std::atomic<int> later{0};
  std::thread releaser;
  {
    OrderedQueue q(4);
    EXPECT_TRUE(q.Push([&] {
                   started = true;
                   gate.wait();
                   return Status::Ok();
                 }).ok());
    while (!started) std::this_thread::yield();  // the first runs: four may wait
    for (int i = 0; i < 4; ++i) {
      EXPECT_TRUE(q.Push([&] {
                     ++later;
                     return Status::Ok();
                   }).ok());
    }
    releaser = std::thread([&] {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      release.set_value();
    });
  }  // waits for the running task only
  releaser.join();
  EXPECT_EQ(later.load(), 0);
}

}  // namespace
}  // namespace fvv
