// SPDX-License-Identifier: Apache-2.0
// RunJob (server/jobs/job_runner.h): a popped job runs to its end on the calling thread with the
// job's own interrupter, and every way it can end is recorded in the job and in the metrics: a
// valid result, a cancellation before it started (no solve, no queue wait), a cancellation while
// it runs (an interrupted solve, timed), and a solver error (a client's error as itself).
#include "server/jobs/job_runner.h"

#include <memory>
#include <string>
#include <vector>

#include "core/mesh_stats.h"
#include "core/proto/mesh_stats_proto.h"
#include "core/proto/quantization_proto.h"
#include "core/quantization_validator.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "tests/server/server_test_jobs.h"
#include "tests/support/test_data.h"
#include "tests/support/tmesh_copies.h"

namespace ispq::server {
namespace {

using ::testing::HasSubstr;

v1::ServerStats StatsOf(const ServerMetrics& metrics) {
  v1::ServerStats stats;
  metrics.FillProto(stats);
  return stats;
}

// Whether the validator's verdict on the result's q is the verdict the result reports.
void ExpectValidatorAgrees(const TMesh& mesh, const v1::QuantizationResult& result) {
  const absl::StatusOr<std::vector<int64_t>> q = QuantizationFromProto(result, mesh);
  ASSERT_TRUE(q.ok()) << q.status();
  const absl::StatusOr<ValidationReport> report = ValidateQuantization(mesh, *q);
  ASSERT_TRUE(report.ok()) << report.status();
  EXPECT_EQ(report->valid(), result.valid()) << report->Describe();
}

TEST(JobRunnerTest, AJobRunsToAValidResultAndIsCountedAsSucceeded) {
  ServerMetrics metrics;
  const std::shared_ptr<Job> job = NewNotchJob("ok");
  const std::shared_ptr<const TMesh> mesh = job->spec().mesh;
  RunJob(*job, metrics);
  ASSERT_TRUE(job->done());
  const v1::Job proto = job->ToProto(v1::FULL);
  EXPECT_EQ(proto.state(), v1::SUCCEEDED);
  ASSERT_TRUE(proto.has_result());
  EXPECT_TRUE(proto.result().valid());
  ExpectValidatorAgrees(*mesh, proto.result());
  EXPECT_TRUE(proto.has_start_time());
  const v1::ServerStats stats = StatsOf(metrics);
  EXPECT_EQ(stats.finished_total().succeeded(), 1);
  EXPECT_EQ(stats.solve_seconds().count(), 1);
  EXPECT_EQ(stats.queue_wait_seconds().count(), 1);
}

TEST(JobRunnerTest, AJobCancelledBeforeItStartedEndsWithoutASolve) {
  ServerMetrics metrics;
  const std::shared_ptr<Job> job = NewNotchJob("cancelled");
  job->RequestCancel();
  RunJob(*job, metrics);
  ASSERT_TRUE(job->done());
  const v1::Job proto = job->ToProto(v1::FULL);
  EXPECT_EQ(proto.state(), v1::CANCELLED);
  EXPECT_FALSE(proto.has_start_time());
  EXPECT_EQ(proto.error().code(), static_cast<int>(absl::StatusCode::kCancelled));
  EXPECT_THAT(proto.error().message(), HasSubstr("before it started"));
  const v1::ServerStats stats = StatsOf(metrics);
  EXPECT_EQ(stats.finished_total().cancelled(), 1);
  EXPECT_EQ(stats.solve_seconds().count(), 0);
  EXPECT_EQ(stats.queue_wait_seconds().count(), 0) << "it never left the queue for a worker";
}

// Cancels its job at the first event after the job started (its first progress report), from
// inside the solve.
class CancelOnFirstProgress : public JobWatcher {
 public:
  explicit CancelOnFirstProgress(Job* job) : job_(job) {}
  void OnJobEvent() override {
    if (job_->state() == v1::RUNNING) job_->RequestCancel();
  }

 private:
  Job* const job_;
};

// The run gets the job's interrupter: a cancellation stops the solve, which returns what it has.
TEST(JobRunnerTest, ACancellationWhileRunningInterruptsTheSolve) {
  ServerMetrics metrics;
  JobSpec spec = NotchJobSpec();
  // Twenty notches: far more LP solves than the first progress report comes after.
  auto copies = std::make_shared<const TMesh>(testing::TMeshOrDie(testing::DisjointCopies(
      testing::LoadProtoOrDie(testing::RealTMeshPath("hex-me/s07c_notch.tmesh.json")), 20)));
  spec.mesh = copies;
  spec.mesh_stats = MeshStatsToProto(ComputeMeshStats(*copies));
  const auto job = std::make_shared<Job>("interrupted", std::move(spec), false, 0, absl::Now());
  const auto watcher = std::make_shared<CancelOnFirstProgress>(job.get());
  job->AddWatcher(watcher);
  RunJob(*job, metrics);
  ASSERT_TRUE(job->done());
  const v1::Job proto = job->ToProto(v1::FULL);
  EXPECT_EQ(proto.state(), v1::CANCELLED);
  ASSERT_TRUE(proto.has_result());
  EXPECT_EQ(proto.result().termination(), v1::INTERRUPTED);
  ExpectValidatorAgrees(*copies, proto.result());
  const v1::ServerStats stats = StatsOf(metrics);
  EXPECT_EQ(stats.finished_total().cancelled(), 1);
  EXPECT_EQ(stats.solve_seconds().count(), 1) << "the interrupted solve ran";
}

// Options the solver refuses are the client's error: INVALID_ARGUMENT as the solver said it, not
// an INTERNAL failure of the server.
TEST(JobRunnerTest, ASolverErrorEndsTheJobFailedWithTheSolversStatus) {
  ServerMetrics metrics;
  JobSpec spec = NotchJobSpec();
  spec.options.scaling = -1;
  Job job("failed", std::move(spec), false, 0, absl::Now());
  RunJob(job, metrics);
  ASSERT_TRUE(job.done());
  const v1::Job proto = job.ToProto(v1::FULL);
  EXPECT_EQ(proto.state(), v1::FAILED);
  EXPECT_EQ(proto.error().code(), static_cast<int>(absl::StatusCode::kInvalidArgument));
  EXPECT_THAT(proto.error().message(), HasSubstr("scaling"));
  const v1::ServerStats stats = StatsOf(metrics);
  EXPECT_EQ(stats.finished_total().failed(), 1);
  EXPECT_EQ(stats.solve_seconds().count(), 0);
  EXPECT_EQ(stats.queue_wait_seconds().count(), 1);
}

}  // namespace
}  // namespace ispq::server
