// SPDX-License-Identifier: Apache-2.0
#include "server/admission/admission_pool.h"

#include <atomic>
#include <memory>

#include "absl/synchronization/notification.h"
#include "gtest/gtest.h"

namespace ispq::server {
namespace {

TEST(AdmissionPoolTest, RefusesBeyondItsWaitingRoomAndRunsTheRestInOrder) {
  std::vector<int> ran;
  absl::Notification release;
  absl::Notification started;
  {
    AdmissionPool pool(/*threads=*/1, /*max_waiting=*/2);
    ASSERT_TRUE(pool.TrySchedule([&] {
      started.Notify();
      release.WaitForNotification();
      ran.push_back(0);
    }));
    started.WaitForNotification();  // the first is running, not waiting
    EXPECT_TRUE(pool.TrySchedule([&] { ran.push_back(1); }));
    EXPECT_TRUE(pool.TrySchedule([&] { ran.push_back(2); }));
    EXPECT_TRUE(pool.full());
    EXPECT_FALSE(pool.TrySchedule([&] { ran.push_back(3); }));
    EXPECT_EQ(pool.in_progress(), 3);
    release.Notify();
  }  // the destructor runs what is waiting, then joins
  EXPECT_EQ(ran, (std::vector<int>{0, 1, 2}));
}

TEST(AdmissionPoolTest, RunsTasksOnSeveralThreads) {
  std::atomic<int> ran = 0;
  {
    AdmissionPool pool(/*threads=*/3, /*max_waiting=*/100);
    for (int i = 0; i < 50; ++i) ASSERT_TRUE(pool.TrySchedule([&] { ++ran; }));
  }
  EXPECT_EQ(ran, 50);
}

}  // namespace
}  // namespace ispq::server
