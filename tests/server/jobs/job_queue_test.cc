// SPDX-License-Identifier: Apache-2.0
#include "server/jobs/job_queue.h"

#include <thread>

#include "gtest/gtest.h"
#include "tests/server/server_test_jobs.h"

namespace ispq::server {
namespace {

TEST(JobQueueTest, RefusesBeyondCapacityAndRemovesWaitingJobs) {
  JobQueue queue(2);
  std::shared_ptr<Job> a = NewNotchJob("a");
  std::shared_ptr<Job> b = NewNotchJob("b");
  ASSERT_TRUE(queue.Push(a).ok());
  ASSERT_TRUE(queue.Push(b).ok());
  EXPECT_EQ(queue.Push(NewNotchJob("c")).code(), absl::StatusCode::kResourceExhausted);
  EXPECT_TRUE(queue.Remove(*a));
  EXPECT_FALSE(queue.Remove(*a));
  EXPECT_EQ(queue.waiting(), 1);
  EXPECT_EQ(queue.Pop(), b);
  EXPECT_EQ(queue.held(), 1);
  EXPECT_FALSE(queue.Remove(*b)) << "a popped job belongs to its worker";
  EXPECT_FALSE(queue.WaitUntilIdle(absl::Now() + absl::Milliseconds(10)));
  queue.MarkDone();
  EXPECT_TRUE(queue.WaitUntilIdle(absl::Now()));
}

TEST(JobQueueTest, ClosingHandsBackWaitingJobsAndRefusesNewOnes) {
  JobQueue queue(4);
  ASSERT_TRUE(queue.Push(NewNotchJob("a")).ok());
  ASSERT_TRUE(queue.Push(NewNotchJob("b")).ok());
  const std::vector<std::shared_ptr<Job>> drained = queue.CloseAndDrain();
  ASSERT_EQ(drained.size(), 2u);
  EXPECT_EQ(drained[0]->id(), "a");
  EXPECT_EQ(queue.Push(NewNotchJob("c")).code(), absl::StatusCode::kUnavailable);
  EXPECT_EQ(queue.Pop(), nullptr);
  EXPECT_TRUE(queue.closed());
}

TEST(JobQueueTest, ClosingReleasesAWorkerWaitingForJobs) {
  JobQueue queue(4);
  std::shared_ptr<Job> popped = NewNotchJob("placeholder");
  std::thread worker([&] { popped = queue.Pop(); });
  EXPECT_TRUE(queue.CloseAndDrain().empty());
  worker.join();
  EXPECT_EQ(popped, nullptr);
}

}  // namespace
}  // namespace ispq::server
