// SPDX-License-Identifier: Apache-2.0
// The job's state machine on its own (server/model/job.h): transitions, the terminal event,
// cancellation before and during a run, the stream protocol and watchers. The service exercises the
// same job end to end in tests/integration; these cases pin each transition without a server.
#include "server/model/job.h"

#include <memory>

#include "absl/status/status.h"
#include "absl/time/clock.h"
#include "gtest/gtest.h"
#include "tests/server/server_test_jobs.h"

namespace ispq::server {
namespace {

v1::QuantizationResult Result(v1::Termination termination) {
  v1::QuantizationResult result;
  result.set_valid(true);
  result.set_termination(termination);
  return result;
}

class CountingWatcher : public JobWatcher {
 public:
  void OnJobEvent() override { ++notifications; }
  int notifications = 0;
};

TEST(JobTest, StartsQueuedWithItsAcceptedEvent) {
  const std::shared_ptr<Job> job = NewNotchJob("a");
  EXPECT_EQ(job->state(), v1::QUEUED);
  EXPECT_FALSE(job->done());
  EXPECT_FALSE(job->end_time().has_value());
  const Job::StreamStep first = job->NextForStream(0);
  ASSERT_TRUE(first.event.has_value());
  EXPECT_TRUE(first.event->has_accepted());
  EXPECT_EQ(first.event->sequence(), 0);
  EXPECT_EQ(first.event->job(), "jobs/a");
  // Nothing more yet, and not ended: the stream waits.
  const Job::StreamStep next = job->NextForStream(1);
  EXPECT_FALSE(next.event.has_value());
  EXPECT_FALSE(next.final_status.has_value());
}

TEST(JobTest, RunsToSuccessAndEndsTheStreamWithOk) {
  const std::shared_ptr<Job> job = NewNotchJob("b");
  ASSERT_TRUE(job->Start(absl::Now()));
  EXPECT_EQ(job->state(), v1::RUNNING);
  v1::Progress progress;
  progress.set_objective(12.5);
  job->PublishProgress(progress);
  job->FinishWithResult(Result(v1::CONVERGED), absl::Now());
  EXPECT_EQ(job->state(), v1::SUCCEEDED);
  EXPECT_TRUE(job->done());
  EXPECT_TRUE(job->end_time().has_value());
  EXPECT_EQ(job->NextForStream(1).event->progress().objective(), 12.5);
  const Job::StreamStep terminal = job->NextForStream(2);
  ASSERT_TRUE(terminal.event.has_value());
  EXPECT_TRUE(terminal.event->has_result());
  const Job::StreamStep after = job->NextForStream(3);
  EXPECT_FALSE(after.event.has_value());
  ASSERT_TRUE(after.final_status.has_value());
  EXPECT_TRUE(after.final_status->ok());
}

TEST(JobTest, AnErrorFailsTheJobAndIsTheStreamsFinalStatus) {
  const std::shared_ptr<Job> job = NewNotchJob("c");
  ASSERT_TRUE(job->Start(absl::Now()));
  job->FinishWithError(absl::InternalError("solver broke"), absl::Now());
  EXPECT_EQ(job->state(), v1::FAILED);
  const Job::StreamStep terminal = job->NextForStream(1);
  ASSERT_TRUE(terminal.event.has_value());
  EXPECT_EQ(terminal.event->error().code(), static_cast<int>(absl::StatusCode::kInternal));
  EXPECT_EQ(terminal.event->error().message(), "solver broke");
  const Job::StreamStep after = job->NextForStream(2);
  ASSERT_TRUE(after.final_status.has_value());
  EXPECT_EQ(after.final_status->code(), absl::StatusCode::kInternal);
}

TEST(JobTest, ACancelledQueuedJobNeverStarts) {
  const std::shared_ptr<Job> job = NewNotchJob("d");
  job->RequestCancel();
  EXPECT_TRUE(job->interrupter().IsInterrupted());
  EXPECT_FALSE(job->Start(absl::Now()));
  EXPECT_EQ(job->state(), v1::QUEUED) << "the owner ends it, not RequestCancel";
  job->FinishWithError(absl::CancelledError("cancelled before it ran"), absl::Now());
  EXPECT_EQ(job->state(), v1::CANCELLED);
}

TEST(JobTest, AnInterruptedRunIsCancelledOnlyIfSomeoneAskedForIt) {
  const std::shared_ptr<Job> asked = NewNotchJob("e");
  ASSERT_TRUE(asked->Start(absl::Now()));
  asked->RequestCancel();
  asked->FinishWithResult(Result(v1::INTERRUPTED), absl::Now());
  EXPECT_EQ(asked->state(), v1::CANCELLED);

  // Interrupted for another reason (the server stopping): the result stands.
  const std::shared_ptr<Job> stopped = NewNotchJob("f");
  ASSERT_TRUE(stopped->Start(absl::Now()));
  stopped->FinishWithResult(Result(v1::INTERRUPTED), absl::Now());
  EXPECT_EQ(stopped->state(), v1::SUCCEEDED);
}

TEST(JobTest, AnAbandonedRunEndsWithTheAbandonReasonWhateverItReturns) {
  const std::shared_ptr<Job> job = NewNotchJob("a");
  ASSERT_TRUE(job->Start(absl::Now()));
  job->Abandon(absl::UnavailableError("another replica runs this job now"));
  EXPECT_TRUE(job->interrupter().IsInterrupted());
  EXPECT_FALSE(job->done()) << "the worker still runs it and ends it";
  job->Abandon(absl::InternalError("a later reason"));  // the first one wins
  job->FinishWithResult(Result(v1::CONVERGED), absl::Now());
  EXPECT_EQ(job->state(), v1::FAILED);
  const v1::Job ended = job->ToProto(v1::FULL);
  EXPECT_FALSE(ended.has_result());
  EXPECT_EQ(ended.error().code(), static_cast<int32_t>(absl::StatusCode::kUnavailable));
  EXPECT_EQ(ended.error().message(), "another replica runs this job now");

  // Queued: it never starts, and the worker's "cancelled before it started" becomes the reason.
  const std::shared_ptr<Job> queued = NewNotchJob("b");
  queued->Abandon(absl::UnavailableError("lease lost"));
  EXPECT_FALSE(queued->Start(absl::Now()));
  queued->FinishWithError(absl::CancelledError("cancelled before it started"), absl::Now());
  EXPECT_EQ(queued->state(), v1::FAILED);
  EXPECT_EQ(queued->ToProto(v1::FULL).error().message(), "lease lost");
}

TEST(JobTest, TheFirstEndWinsAndLaterOnesChangeNothing) {
  const std::shared_ptr<Job> job = NewNotchJob("g");
  ASSERT_TRUE(job->Start(absl::Now()));
  job->FinishWithResult(Result(v1::CONVERGED), absl::Now());
  job->FinishWithError(absl::InternalError("late"), absl::Now());
  job->RequestCancel();
  EXPECT_EQ(job->state(), v1::SUCCEEDED);
  EXPECT_FALSE(job->interrupter().IsInterrupted()) << "no effect once done";
  // Accepted (0), the result (1), nothing after it: the late error left no event.
  EXPECT_TRUE(job->NextForStream(1).event->has_result());
  const Job::StreamStep after = job->NextForStream(2);
  EXPECT_FALSE(after.event.has_value());
  ASSERT_TRUE(after.final_status.has_value());
  EXPECT_TRUE(after.final_status->ok());
}

TEST(JobTest, WatchersHearOfPastEventsAtOnceAndOfEveryNewOne) {
  const std::shared_ptr<Job> job = NewNotchJob("h");
  auto watcher = std::make_shared<CountingWatcher>();
  job->AddWatcher(watcher);
  EXPECT_EQ(watcher->notifications, 1) << "the accepted event exists already";
  ASSERT_TRUE(job->Start(absl::Now()));
  job->PublishProgress(v1::Progress());
  job->PublishIntermediate(v1::IntermediateQuantization());
  job->FinishWithResult(Result(v1::CONVERGED), absl::Now());
  EXPECT_EQ(watcher->notifications, 4);
  // An expired watcher is not called (and not kept alive by the job).
  const std::shared_ptr<Job> other = NewNotchJob("i");
  std::weak_ptr<CountingWatcher> gone;
  {
    auto temporary = std::make_shared<CountingWatcher>();
    gone = temporary;
    other->AddWatcher(temporary);
  }
  EXPECT_TRUE(gone.expired());
  other->PublishProgress(v1::Progress());
}

TEST(JobTest, AnEndedJobLetsGoOfItsMesh) {
  const std::shared_ptr<Job> job = NewNotchJob("j");
  EXPECT_NE(job->spec().mesh, nullptr);
  ASSERT_TRUE(job->Start(absl::Now()));
  job->FinishWithResult(Result(v1::CONVERGED), absl::Now());
  EXPECT_EQ(job->spec().mesh, nullptr);
}

}  // namespace
}  // namespace ispq::server
