// SPDX-License-Identifier: Apache-2.0
// The job side of the server with the in-memory store (server/jobs/job_scheduler.h): a job runs
// to a valid result; a full queue refuses with a retry hint; a queued job is cancelled at once and
// frees its place; shutdown ends the queued jobs UNAVAILABLE and refuses new ones. With no worker
// threads, jobs stay queued for as long as a test needs them there.
#include "server/jobs/job_scheduler.h"

#include <memory>
#include <vector>

#include "core/proto/quantization_proto.h"
#include "core/quantization_validator.h"
#include "gtest/gtest.h"
#include "server/jobs/retry_hint.h"
#include "tests/server/server_test_jobs.h"
#include "tests/support/bounded_wait.h"

namespace ispq::server {
namespace {

std::shared_ptr<Job> SubmitOrDie(JobScheduler& scheduler) {
  absl::StatusOr<std::shared_ptr<Job>> job = scheduler.Submit(NotchJobSpec(), false);
  EXPECT_TRUE(job.ok()) << job.status();
  return job.ok() ? *job : nullptr;
}

TEST(JobSchedulerTest, RunsASubmittedJobToAValidResult) {
  ServerMetrics metrics;
  JobScheduler scheduler({.workers = 1, .max_queued_jobs = 4, .retention = {}}, metrics);
  const std::shared_ptr<Job> job = SubmitOrDie(scheduler);
  ASSERT_NE(job, nullptr);
  ASSERT_TRUE(testing::WaitUntil([&] { return job->done(); }));
  EXPECT_EQ(job->state(), v1::SUCCEEDED);
  EXPECT_EQ(scheduler.Find(job->id()), job);

  const v1::Job proto = job->ToProto(v1::FULL);
  const TMesh& mesh = *NotchJobSpec().mesh;
  const absl::StatusOr<std::vector<int64_t>> q = QuantizationFromProto(proto.result(), mesh);
  ASSERT_TRUE(q.ok()) << q.status();
  const absl::StatusOr<ValidationReport> report = ValidateQuantization(mesh, *q);
  ASSERT_TRUE(report.ok()) << report.status();
  EXPECT_TRUE(report->valid()) << report->Describe();
  EXPECT_TRUE(proto.result().valid());
}

TEST(JobSchedulerTest, AFullQueueRefusesWithARetryHint) {
  ServerMetrics metrics;
  JobScheduler scheduler({.workers = 0, .max_queued_jobs = 2, .retention = {}}, metrics);
  SubmitOrDie(scheduler);
  SubmitOrDie(scheduler);
  EXPECT_TRUE(scheduler.queue_full());
  const absl::StatusOr<std::shared_ptr<Job>> refused = scheduler.Submit(NotchJobSpec(), false);
  EXPECT_EQ(refused.status().code(), absl::StatusCode::kResourceExhausted);
  EXPECT_TRUE(RetryHintOf(refused.status()).has_value()) << refused.status();
  v1::ServerStats stats;
  metrics.FillProto(stats);
  EXPECT_EQ(stats.rejected_queue_full_total(), 1);
}

TEST(JobSchedulerTest, ACancelledQueuedJobEndsAtOnceAndFreesItsPlace) {
  ServerMetrics metrics;
  JobScheduler scheduler({.workers = 0, .max_queued_jobs = 1, .retention = {}}, metrics);
  const std::shared_ptr<Job> job = SubmitOrDie(scheduler);
  ASSERT_NE(job, nullptr);
  ASSERT_TRUE(scheduler.queue_full());
  scheduler.Cancel(*job);
  EXPECT_TRUE(job->done());
  EXPECT_EQ(job->state(), v1::CANCELLED);
  EXPECT_FALSE(scheduler.queue_full());
  EXPECT_NE(SubmitOrDie(scheduler), nullptr);
  scheduler.Cancel(*job);  // again, once done: no effect
  EXPECT_EQ(job->state(), v1::CANCELLED);
}

TEST(JobSchedulerTest, ShutdownEndsQueuedJobsUnavailableAndRefusesNewOnes) {
  ServerMetrics metrics;
  JobScheduler scheduler({.workers = 0, .max_queued_jobs = 4, .retention = {}}, metrics);
  const std::shared_ptr<Job> first = SubmitOrDie(scheduler);
  const std::shared_ptr<Job> second = SubmitOrDie(scheduler);
  ASSERT_NE(first, nullptr);
  ASSERT_NE(second, nullptr);
  scheduler.StopAccepting();
  EXPECT_FALSE(scheduler.accepting());
  for (const std::shared_ptr<Job>& job : {first, second}) {
    EXPECT_TRUE(job->done());
    EXPECT_EQ(job->state(), v1::FAILED);
    EXPECT_EQ(job->ToProto(v1::FULL).error().code(),
              static_cast<int32_t>(absl::StatusCode::kUnavailable));
  }
  EXPECT_EQ(scheduler.Submit(NotchJobSpec(), false).status().code(),
            absl::StatusCode::kUnavailable);
  EXPECT_TRUE(scheduler.WaitUntilIdle(absl::Now()));
}

}  // namespace
}  // namespace ispq::server
