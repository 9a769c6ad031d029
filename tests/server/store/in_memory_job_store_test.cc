// SPDX-License-Identifier: Apache-2.0
// What is InMemoryJobStore's own (server/store/in_memory_job_store.h); the contract both stores
// keep (retention, listing, eviction) is job_store_test.cc's. This store holds the job objects
// themselves, resolves no request ids, leaves queued jobs to the scheduler on cancellation, and
// is never shared nor unreachable.
#include "server/store/in_memory_job_store.h"

#include <memory>
#include <string>
#include <vector>

#include "gtest/gtest.h"
#include "tests/server/server_test_jobs.h"

namespace ispq::server {
namespace {

const absl::Time kT0 = absl::FromUnixSeconds(1'000'000);

TEST(InMemoryJobStoreTest, AnswersWithTheJobObjectsItWasGiven) {
  InMemoryJobStore store({});
  std::shared_ptr<Job> job = NewNotchJob("j", kT0);
  absl::StatusOr<std::shared_ptr<Job>> added = store.Add(job, "ignored request", kT0);
  ASSERT_TRUE(added.ok());
  EXPECT_EQ(*added, job);
  EXPECT_EQ(store.Find("j", kT0), job);
  absl::StatusOr<std::shared_ptr<Job>> looked_up = store.Lookup("j", kT0);
  ASSERT_TRUE(looked_up.ok());
  EXPECT_EQ(*looked_up, job);
  absl::StatusOr<std::shared_ptr<Job>> unknown = store.Lookup("unknown", kT0);
  ASSERT_TRUE(unknown.ok()) << "a store in this process always answers";
  EXPECT_EQ(*unknown, nullptr);
}

// Request ids are resolved before the store (server/admission/request_ids.h): two jobs with the
// same one are two jobs here.
TEST(InMemoryJobStoreTest, AddsEveryJobWhateverItsRequestId) {
  InMemoryJobStore store({});
  for (const std::string id : {"first", "second"}) {
    JobSpec spec = NotchJobSpec();
    spec.request_id = "r1";
    spec.request_fingerprint = id;  // a different request, even
    auto job = std::make_shared<Job>(id, std::move(spec), false, 0, kT0);
    absl::StatusOr<std::shared_ptr<Job>> added = store.Add(job, "", kT0);
    ASSERT_TRUE(added.ok()) << added.status();
    EXPECT_EQ(*added, job);
  }
  EXPECT_NE(store.Find("first", kT0), nullptr);
  EXPECT_NE(store.Find("second", kT0), nullptr);
}

// The scheduler holds the queue and ends what it takes out of it; the store only asks the job
// to stop.
TEST(InMemoryJobStoreTest, CancelAsksTheJobToStopAndEndsNothingItself) {
  InMemoryJobStore store({});
  std::shared_ptr<Job> queued = NewNotchJob("queued", kT0);
  std::shared_ptr<Job> running = NewNotchJob("running", kT0);
  ASSERT_TRUE(store.Add(queued, "", kT0).ok());
  ASSERT_TRUE(store.Add(running, "", kT0).ok());
  ASSERT_TRUE(running->Start(kT0));
  store.Cancel(*queued, kT0);
  store.Cancel(*running, kT0);
  EXPECT_EQ(queued->state(), v1::QUEUED);
  EXPECT_FALSE(queued->Start(kT0)) << "it never starts";
  EXPECT_EQ(running->state(), v1::RUNNING);
  EXPECT_TRUE(running->interrupter().IsInterrupted());
  EXPECT_EQ(store.CountByState().queued(), 1);
  EXPECT_EQ(store.CountByState().running(), 1);
}

// Every job of this store waits or runs in this process: all that have not ended are active.
TEST(InMemoryJobStoreTest, EveryJobNotEndedIsActiveHere) {
  InMemoryJobStore store({});
  std::shared_ptr<Job> queued = NewNotchJob("queued", kT0);
  std::shared_ptr<Job> running = NewNotchJob("running", kT0);
  std::shared_ptr<Job> ended = NewNotchJob("ended", kT0);
  for (const std::shared_ptr<Job>& job : {queued, running, ended}) {
    ASSERT_TRUE(store.Add(job, "", kT0).ok());
  }
  ASSERT_TRUE(running->Start(kT0));
  ended->FinishWithError(absl::InternalError("broke"), kT0);
  std::vector<std::shared_ptr<Job>> active = store.ActiveJobs();
  ASSERT_EQ(active.size(), 2u);
  EXPECT_EQ(active[0], queued);
  EXPECT_EQ(active[1], running);
  EXPECT_FALSE(store.shared());
  EXPECT_TRUE(store.reachable());
  EXPECT_TRUE(store.Flush(kT0)) << "nothing to make durable";
}

}  // namespace
}  // namespace ispq::server
