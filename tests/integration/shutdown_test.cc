// SPDX-License-Identifier: Apache-2.0
// Graceful shutdown of the real server process on SIGTERM/SIGINT: health turns NOT_SERVING, new
// jobs are refused, queued jobs end with UNAVAILABLE so that clients can resubmit, running jobs
// finish (or are interrupted when the grace period runs out) and their watchers receive the
// result before the process exits with code 0. What is asserted is what happened (states,
// terminations, exit codes, log lines), not how long it took: waits are only bounded to stop a
// hang (kSafetyNet), since a loaded 2-core machine makes every step slower.
#include <signal.h>

#include <iostream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "absl/synchronization/notification.h"
#include "absl/time/clock.h"
#include "client/health_check.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "tests/integration/service_test_support.h"
#include "tests/support/bounded_wait.h"

namespace ispq::testing {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

TEST(ShutdownTest, RunningJobsFinishQueuedJobsAreRefusedAndTheProcessExitsCleanly) {
  std::unique_ptr<ServerProcess> server =
      StartServerOrFail({"--workers=1", "--shutdown_grace_seconds=120"});
  ASSERT_NE(server, nullptr);
  client::QuantizerClient client = ClientOf(*server);
  const v1::TMesh mesh = MeshTakingSeconds(4);

  // A job bound to a Quantize call, running when the signal arrives.
  client::JobOutcome running_outcome;
  absl::Notification running;
  std::thread running_call([&] {
    running_outcome = client.Quantize(RequestFor(mesh, 100),
                                      StreamFor(kJobTimeout, [&](const v1::QuantizeEvent& event) {
                                        if (event.has_progress() && !running.HasBeenNotified())
                                          running.Notify();
                                        return true;
                                      }));
  });
  ASSERT_TRUE(running.WaitForNotificationWithTimeout(kSafetyNet));

  // Two queued jobs with watchers.
  std::vector<std::string> queued;
  for (int i = 0; i < 2; ++i) {
    const absl::StatusOr<v1::Job> job = client.SubmitJob(RequestFor(NotchMesh(), 100));
    ASSERT_TRUE(job.ok()) << job.status();
    EXPECT_EQ(job->state(), v1::QUEUED);
    queued.push_back(job->name());
  }
  std::vector<client::JobOutcome> queued_outcomes(queued.size());
  std::vector<std::thread> watchers;
  for (size_t i = 0; i < queued.size(); ++i) {
    watchers.emplace_back(
        [&, i] { queued_outcomes[i] = client.WatchJob(queued[i], 0, StreamFor(kJobTimeout)); });
  }

  server->Signal(SIGTERM);
  // Draining: not serving, refusing jobs, still answering about them.
  absl::StatusOr<client::ServingStatus> health;
  WaitUntil(
      [&] {
        health = client::CheckHealth(client.channel(), "", kSafetyNet);
        return health.ok() && *health == client::ServingStatus::kNotServing;
      },
      kSafetyNet, absl::Milliseconds(20));
  ASSERT_TRUE(health.ok()) << health.status();
  EXPECT_EQ(*health, client::ServingStatus::kNotServing);
  const absl::StatusOr<v1::Job> refused = client.SubmitJob(RequestFor(NotchMesh(), 100));
  EXPECT_EQ(refused.status().code(), absl::StatusCode::kUnavailable) << refused.status();
  const absl::StatusOr<v1::Job> dropped = client.GetJob(queued[0]);
  ASSERT_TRUE(dropped.ok()) << dropped.status();
  EXPECT_EQ(dropped->state(), v1::FAILED);
  EXPECT_EQ(dropped->error().code(), static_cast<int>(absl::StatusCode::kUnavailable));
  const absl::StatusOr<v1::ServerStats> stats = client.GetServerStats();
  ASSERT_TRUE(stats.ok());
  EXPECT_TRUE(stats->shutting_down());

  running_call.join();
  for (std::thread& watcher : watchers) watcher.join();
  ASSERT_TRUE(running_outcome.status.ok()) << running_outcome.status;
  ASSERT_TRUE(running_outcome.result.has_value());
  EXPECT_EQ(running_outcome.result->termination(), v1::CONVERGED);
  EXPECT_TRUE(IsValidResult(mesh, *running_outcome.result));
  for (const client::JobOutcome& outcome : queued_outcomes) {
    EXPECT_TRUE(outcome.job_ended);
    EXPECT_EQ(outcome.status.code(), absl::StatusCode::kUnavailable) << outcome.status;
    EXPECT_THAT(std::string(outcome.status.message()),
                HasSubstr("shut down before the job started; submit it again"));
  }

  EXPECT_EQ(server->WaitForExit(kSafetyNet), 0) << server->Log();
  const std::string log = server->Log();
  EXPECT_THAT(log, HasSubstr("event=signal signal=SIGTERM"));
  EXPECT_THAT(log, HasSubstr("event=shutdown_end"));
  EXPECT_THAT(log, HasSubstr("event=server_exit"));
  EXPECT_THAT(log, Not(HasSubstr("event=shutdown_interrupt")));
}

TEST(ShutdownTest, TheEndOfTheGracePeriodInterruptsRunningJobsAndDeliversTheirResults) {
  // 20 s: the server keeps a quarter of its grace period, at most 5 s, for interrupted jobs to
  // end and deliver their results, and a deployment gets all 5 (Kubernetes' default grace is
  // 30 s). With a 4 s grace that window was 1 s, which a job under TSan on a loaded machine
  // overran (3.2 s from the interrupt to the job's end, 4 busy processes on 2 cores: the watcher
  // got UNAVAILABLE); natively a 50k-arc job ends 20 ms after its interrupt.
  std::unique_ptr<ServerProcess> server =
      StartServerOrFail({"--workers=1", "--shutdown_grace_seconds=20"});
  ASSERT_NE(server, nullptr);
  client::QuantizerClient client = ClientOf(*server);
  const v1::TMesh& mesh = LongRunningMesh();
  const absl::StatusOr<v1::Job> job = client.SubmitJob(RequestFor(mesh, 100));
  ASSERT_TRUE(job.ok()) << job.status();
  ASSERT_TRUE(WaitForState(client, job->name(), v1::RUNNING).ok());
  client::JobOutcome watched;
  absl::Notification watching;
  std::thread watcher([&] {
    watched = client.WatchJob(job->name(), 0, StreamFor(kJobTimeout, [&](const v1::QuantizeEvent&) {
                                if (!watching.HasBeenNotified()) watching.Notify();
                                return true;
                              }));
  });
  watching.WaitForNotification();

  const absl::Time signalled = absl::Now();
  server->Signal(SIGTERM);
  watcher.join();
  const std::optional<int> exit_code = server->WaitForExit(kSafetyNet);
  const absl::Duration took = absl::Now() - signalled;
  EXPECT_EQ(exit_code, 0) << server->Log();
  // Running jobs get all but a quarter of the grace period (here 15 s): a lower bound, which load
  // cannot break. That the period's end interrupted the job (about a minute of solving) rather
  // than the server waiting for it shows in its INTERRUPTED result below; how soon the process
  // is gone after that depends on the machine's load, so it is reported, not asserted.
  EXPECT_GE(took, absl::Seconds(14.5));
  std::cout << "exited " << absl::FormatDuration(took) << " after SIGTERM (grace period 20 s)\n";
  RecordProperty("exit_after_sigterm_ms", static_cast<int>(absl::ToInt64Milliseconds(took)));

  ASSERT_TRUE(watched.status.ok()) << watched.status;
  ASSERT_TRUE(watched.result.has_value());
  EXPECT_EQ(watched.result->termination(), v1::INTERRUPTED);
  if (watched.result->valid()) {
    EXPECT_TRUE(IsValidResult(mesh, *watched.result));
  }
  EXPECT_THAT(server->Log(), HasSubstr("event=shutdown_interrupt"));
  EXPECT_THAT(server->Log(), HasSubstr("event=job_end job=" + job->name() + " state=CANCELLED"));
}

TEST(ShutdownTest, SigintStopsAnIdleServerAtOnce) {
  // "At once": without waiting for its grace period, made longer here than the wait below, so
  // that exiting at all shows it (a 10 s bound on the exit itself was a bet on the load).
  std::unique_ptr<ServerProcess> server = StartServerOrFail({"--shutdown_grace_seconds=3600"});
  ASSERT_NE(server, nullptr);
  const absl::Time signalled = absl::Now();
  server->Signal(SIGINT);
  EXPECT_EQ(server->WaitForExit(kSafetyNet), 0) << server->Log();
  std::cout << "exited " << absl::FormatDuration(absl::Now() - signalled) << " after SIGINT\n";
  EXPECT_THAT(server->Log(), HasSubstr("event=signal signal=SIGINT"));
  EXPECT_THAT(server->Log(), Not(HasSubstr("event=shutdown_interrupt")));
}

}  // namespace
}  // namespace ispq::testing
