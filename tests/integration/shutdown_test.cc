// Graceful shutdown of the real server process on SIGTERM/SIGINT: health turns NOT_SERVING, new
// jobs are refused, queued jobs end with UNAVAILABLE so that clients can resubmit, running jobs
// finish (or are interrupted when the grace period runs out) and their watchers receive the
// result before the process exits with code 0.
#include <signal.h>

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
  ASSERT_TRUE(running.WaitForNotificationWithTimeout(absl::Seconds(120)));

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
  for (int i = 0; i < 500; ++i) {
    health = client::CheckHealth(client.channel(), "", absl::Seconds(10));
    if (health.ok() && *health == client::ServingStatus::kNotServing) break;
    absl::SleepFor(absl::Milliseconds(20));
  }
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

  EXPECT_EQ(server->WaitForExit(absl::Seconds(150)), 0) << server->Log();
  const std::string log = server->Log();
  EXPECT_THAT(log, HasSubstr("event=signal signal=SIGTERM"));
  EXPECT_THAT(log, HasSubstr("event=shutdown_end"));
  EXPECT_THAT(log, HasSubstr("event=server_exit"));
  EXPECT_THAT(log, Not(HasSubstr("event=shutdown_interrupt")));
}

TEST(ShutdownTest, TheEndOfTheGracePeriodInterruptsRunningJobsAndDeliversTheirResults) {
  std::unique_ptr<ServerProcess> server =
      StartServerOrFail({"--workers=1", "--shutdown_grace_seconds=4"});
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
  const std::optional<int> exit_code = server->WaitForExit(absl::Seconds(60));
  const absl::Duration took = absl::Now() - signalled;
  EXPECT_EQ(exit_code, 0) << server->Log();
  // Running jobs get all but a quarter of the grace period (here 3 s), and the process is gone
  // soon after the period ends (an interrupted solve stops at its next check).
  EXPECT_GE(took, absl::Seconds(2.5));
  EXPECT_LT(took, absl::Seconds(30));

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
  std::unique_ptr<ServerProcess> server = StartServerOrFail({});
  ASSERT_NE(server, nullptr);
  const absl::Time signalled = absl::Now();
  server->Signal(SIGINT);
  EXPECT_EQ(server->WaitForExit(absl::Seconds(30)), 0) << server->Log();
  EXPECT_LT(absl::Now() - signalled, absl::Seconds(10));
  EXPECT_THAT(server->Log(), HasSubstr("event=signal signal=SIGINT"));
}

}  // namespace
}  // namespace ispq::testing
