// SPDX-License-Identifier: Apache-2.0
#include "server/http/handler_pool.h"

#include <pthread.h>

#include <atomic>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "absl/synchronization/notification.h"
#include "gtest/gtest.h"
#include "tests/support/bounded_wait.h"

namespace ispq::server::http {
namespace {

using ::ispq::testing::WaitUntil;

TEST(HandlerPoolTest, RunsTasksInTheOrderPosted) {
  // Written by the pool's one thread only, read after the last task's notification.
  std::vector<int> order;
  absl::Notification last_ran;
  HandlerPool pool(1, "order");
  constexpr int kTasks = 50;
  for (int i = 0; i < kTasks; ++i) {
    ASSERT_TRUE(pool.Post([&, i] {
      order.push_back(i);
      if (i == kTasks - 1) last_ran.Notify();
    }));
  }
  ASSERT_TRUE(last_ran.WaitForNotificationWithTimeout(ispq::testing::kSafetyNet));
  pool.Stop();
  ASSERT_EQ(order.size(), static_cast<size_t>(kTasks));
  for (int i = 0; i < kTasks; ++i) EXPECT_EQ(order[i], i);
}

// A slow route holds one thread, not the others: a lookup is still served beside it.
TEST(HandlerPoolTest, RunsTasksOnSeveralThreadsAtOnce) {
  HandlerPool pool(2, "parallel");
  absl::Notification release;
  absl::Notification other_ran;
  ASSERT_TRUE(pool.Post([&] { release.WaitForNotification(); }));
  ASSERT_TRUE(pool.Post([&] { other_ran.Notify(); }));
  EXPECT_TRUE(other_ran.WaitForNotificationWithTimeout(ispq::testing::kSafetyNet));
  release.Notify();
  pool.Stop();
}

// Stop waits for the running task, drops the queued ones (and their captures) and refuses new
// ones: the server then answers their requests itself.
TEST(HandlerPoolTest, StopDropsQueuedTasksAndWaitsForTheRunningOne) {
  auto pool = std::make_unique<HandlerPool>(1, "stop");
  absl::Notification running;
  absl::Notification release;
  std::atomic<bool> running_finished = false;
  std::atomic<bool> queued_ran = false;
  auto capture = std::make_shared<int>(0);
  ASSERT_TRUE(pool->Post([&] {
    running.Notify();
    release.WaitForNotification();
    running_finished = true;
  }));
  ASSERT_TRUE(pool->Post([&queued_ran, capture] { queued_ran = true; }));
  ASSERT_TRUE(running.WaitForNotificationWithTimeout(ispq::testing::kSafetyNet));
  ASSERT_EQ(capture.use_count(), 2);

  std::thread stopper([&] { pool->Stop(); });
  // Post fails from the moment Stop has taken the queue.
  ASSERT_TRUE(WaitUntil([&] { return !pool->Post([] {}); }));
  // The queued task is gone while the running one still runs.
  EXPECT_TRUE(WaitUntil([&] { return capture.use_count() == 1; }));
  release.Notify();
  stopper.join();
  EXPECT_TRUE(running_finished);
  EXPECT_FALSE(queued_ran);
  EXPECT_FALSE(pool->Post([&queued_ran] { queued_ran = true; }));
  pool->Stop();  // idempotent
  pool.reset();  // and so is the destructor's
  EXPECT_FALSE(queued_ran);
}

// Thread names are cut to the kernel's 15 characters rather than left unset.
TEST(HandlerPoolTest, NamesItsThreads) {
  HandlerPool pool(1, "ispq-http-lookup-pool");
  std::string name;  // read after `done`
  absl::Notification done;
  ASSERT_TRUE(pool.Post([&] {
    char buffer[16] = {};
    pthread_getname_np(pthread_self(), buffer, sizeof(buffer));
    name = buffer;
    done.Notify();
  }));
  ASSERT_TRUE(done.WaitForNotificationWithTimeout(ispq::testing::kSafetyNet));
  EXPECT_EQ(name, "ispq-http-looku");
}

}  // namespace
}  // namespace ispq::server::http
