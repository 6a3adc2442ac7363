// The node's worker queue: a job waiting under a key is replaced by a newer one with that key (the
// latest body, the latest fit), waiting(key) tells whether one is waiting, and the running job is
// never interrupted.
#include "virtual_tryon/ros/job_queue.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>

using virtual_tryon::LatestJobQueue;

TEST(LatestJobQueue, ANewerJobReplacesTheWaitingOneWithItsKey) {
  LatestJobQueue queue;
  std::mutex m;
  std::condition_variable cv;
  bool release = false, started = false;
  std::atomic<int> ranBody{0}, lastBody{0}, ranFit{0};
  queue.post("fit", [&] {
    {
      std::unique_lock<std::mutex> l(m);
      started = true;
      cv.notify_all();
      cv.wait(l, [&] { return release; });
    }
    ++ranFit;
  });
  {
    std::unique_lock<std::mutex> l(m);
    cv.wait(l, [&] { return started; });  // the first job runs and holds the worker
  }
  EXPECT_FALSE(queue.waiting("body"));
  EXPECT_FALSE(queue.post("body", [&] { ++ranBody; lastBody = 1; }));
  EXPECT_TRUE(queue.waiting("body"));
  EXPECT_FALSE(queue.waiting("fit"));  // running, not waiting
  EXPECT_TRUE(queue.post("body", [&] { ++ranBody; lastBody = 2; }));
  EXPECT_EQ(queue.replaced(), 1u);
  EXPECT_EQ(queue.waiting(), 1u);
  {
    std::lock_guard<std::mutex> l(m);
    release = true;
  }
  cv.notify_all();
  queue.waitIdle();
  EXPECT_EQ(ranFit, 1);
  EXPECT_EQ(ranBody, 1);
  EXPECT_EQ(lastBody, 2);
  EXPECT_FALSE(queue.waiting("body"));
}
