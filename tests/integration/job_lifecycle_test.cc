// SPDX-License-Identifier: Apache-2.0
// Jobs as resources: SubmitJob returns at once, the job runs whether or not anyone watches,
// WatchJob resumes where a stream broke off, GetJob/ListJobs answer about it, CancelJob stops
// it, and finished jobs stay retrievable within the retention limits.
#include <iostream>
#include <string>
#include <thread>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/synchronization/notification.h"
#include "absl/time/clock.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "tests/integration/service_test_support.h"
#include "tests/support/bounded_wait.h"

namespace ispq::testing {
namespace {

using ::testing::HasSubstr;

std::vector<std::string> NamesOf(const v1::ListJobsResponse& response) {
  std::vector<std::string> names;
  for (const v1::Job& job : response.jobs()) names.push_back(job.name());
  return names;
}

TEST(JobLifecycleTest, SubmittedJobRunsToAValidResultAndIsListed) {
  std::unique_ptr<ServerProcess> server = StartServerOrFail({"--workers=2"});
  ASSERT_NE(server, nullptr);
  client::QuantizerClient client = ClientOf(*server);
  const v1::TMesh& mesh = NotchMesh();

  const absl::StatusOr<v1::Job> submitted = client.SubmitJob(RequestFor(mesh, 25));
  ASSERT_TRUE(submitted.ok()) << submitted.status();
  EXPECT_FALSE(submitted->bound_to_call());
  EXPECT_GE(submitted->event_count(), 1);  // the accepted event exists from the start
  EXPECT_EQ(submitted->mesh_stats().arcs(), mesh.arcs_size());
  EXPECT_EQ(submitted->options().scaling().level_percent(), 25);

  const absl::StatusOr<v1::Job> done = WaitUntilDone(client, submitted->name());
  ASSERT_TRUE(done.ok()) << done.status();
  EXPECT_EQ(done->state(), v1::SUCCEEDED);
  ASSERT_TRUE(done->has_result());
  EXPECT_TRUE(IsValidResult(mesh, done->result()));
  EXPECT_TRUE(done->has_start_time() && done->has_end_time());

  v1::ListJobsRequest all;
  const absl::StatusOr<v1::ListJobsResponse> listed = client.ListJobs(all);
  ASSERT_TRUE(listed.ok()) << listed.status();
  ASSERT_EQ(listed->jobs_size(), 1);
  EXPECT_EQ(listed->jobs(0).name(), submitted->name());
  EXPECT_EQ(listed->jobs(0).result().q_size(), 0) << "ListJobs defaults to the basic view";
  EXPECT_GT(listed->jobs(0).result().objective(), 0);

  v1::ListJobsRequest running;
  running.set_state(v1::RUNNING);
  const absl::StatusOr<v1::ListJobsResponse> none = client.ListJobs(running);
  ASSERT_TRUE(none.ok());
  EXPECT_EQ(none->jobs_size(), 0);
}

TEST(JobLifecycleTest, ListJobsPagesNewestFirst) {
  std::unique_ptr<ServerProcess> server = StartServerOrFail({"--workers=2"});
  ASSERT_NE(server, nullptr);
  client::QuantizerClient client = ClientOf(*server);
  const absl::StatusOr<v1::Mesh> stored = client.CreateMesh(NotchMesh());
  ASSERT_TRUE(stored.ok());
  std::vector<std::string> submitted;
  for (int i = 0; i < 5; ++i) {
    const absl::StatusOr<v1::Job> job = client.SubmitJob(StoredMeshRequest(stored->name(), 10));
    ASSERT_TRUE(job.ok()) << job.status();
    submitted.insert(submitted.begin(), job->name());  // newest first
  }
  std::vector<std::string> listed;
  v1::ListJobsRequest request;
  request.set_page_size(2);
  int pages = 0;
  do {
    const absl::StatusOr<v1::ListJobsResponse> page = client.ListJobs(request);
    ASSERT_TRUE(page.ok()) << page.status();
    EXPECT_LE(page->jobs_size(), 2);
    for (const std::string& name : NamesOf(*page)) listed.push_back(name);
    request.set_page_token(page->next_page_token());
    ++pages;
  } while (!request.page_token().empty() && pages < 10);
  EXPECT_EQ(listed, submitted);
  EXPECT_EQ(pages, 3);
}

TEST(JobLifecycleTest, WatchingAFinishedJobReplaysItsKeptEvents) {
  std::unique_ptr<ServerProcess> server = StartServerOrFail({});
  ASSERT_NE(server, nullptr);
  client::QuantizerClient client = ClientOf(*server);
  const absl::StatusOr<v1::Job> submitted = client.SubmitJob(RequestFor(NotchMesh(), 100));
  ASSERT_TRUE(submitted.ok()) << submitted.status();
  const absl::StatusOr<v1::Job> done = WaitUntilDone(client, submitted->name());
  ASSERT_TRUE(done.ok()) << done.status();

  std::vector<v1::QuantizeEvent> events;
  const client::JobOutcome replay =
      client.WatchJob(done->name(), 0, StreamFor(kJobTimeout, [&](const v1::QuantizeEvent& e) {
                        events.push_back(e);
                        return true;
                      }));
  ASSERT_TRUE(replay.status.ok()) << replay.status;
  ASSERT_TRUE(replay.result.has_value());
  EXPECT_TRUE(IsValidResult(NotchMesh(), *replay.result));
  // Kept: the accepted event, the latest progress (and intermediate), the result.
  ASSERT_GE(events.size(), 2u);
  ASSERT_LE(events.size(), 4u);
  EXPECT_TRUE(events.front().has_accepted());
  EXPECT_TRUE(events.back().has_result());
  EXPECT_EQ(events.back().sequence(), done->event_count() - 1);

  // From the terminal event's number: just the result.
  events.clear();
  const client::JobOutcome last =
      client.WatchJob(done->name(), done->event_count() - 1,
                      StreamFor(kJobTimeout, [&](const v1::QuantizeEvent& e) {
                        events.push_back(e);
                        return true;
                      }));
  ASSERT_TRUE(last.status.ok()) << last.status;
  ASSERT_EQ(events.size(), 1u);
  EXPECT_TRUE(events[0].has_result());

  // Past the end: nothing to send, and the client says so.
  const client::JobOutcome past =
      client.WatchJob(done->name(), done->event_count(), StreamFor(kJobTimeout));
  EXPECT_FALSE(past.job_ended);
  EXPECT_EQ(past.status.code(), absl::StatusCode::kOutOfRange) << past.status;
}

TEST(JobLifecycleTest, WatcherDisconnectLeavesTheJobRunningAndWatchJobResumes) {
  std::unique_ptr<ServerProcess> server = StartServerOrFail({"--workers=1"});
  ASSERT_NE(server, nullptr);
  client::QuantizerClient client = ClientOf(*server);
  const v1::TMesh mesh = MeshTakingSeconds(2);
  const absl::StatusOr<v1::Job> submitted = client.SubmitJob(RequestFor(mesh, 100));
  ASSERT_TRUE(submitted.ok()) << submitted.status();

  // The client goes away after the first event.
  const client::JobOutcome broken = client.WatchJob(
      submitted->name(), 0, StreamFor(kJobTimeout, [](const v1::QuantizeEvent&) { return false; }));
  EXPECT_FALSE(broken.job_ended);
  EXPECT_EQ(broken.status.code(), absl::StatusCode::kCancelled);
  EXPECT_EQ(broken.next_event, 1);
  const absl::StatusOr<v1::Job> meanwhile = client.GetJob(submitted->name(), v1::BASIC);
  ASSERT_TRUE(meanwhile.ok());
  EXPECT_FALSE(meanwhile->state() == v1::CANCELLED || meanwhile->state() == v1::FAILED);

  // It comes back and resumes after the event it had.
  std::vector<int64_t> sequences;
  const client::JobOutcome resumed =
      client.FollowJob(submitted->name(), broken.next_event,
                       StreamFor(kJobTimeout, [&](const v1::QuantizeEvent& event) {
                         sequences.push_back(event.sequence());
                         return true;
                       }));
  ASSERT_TRUE(resumed.status.ok()) << resumed.status << "\n" << server->Log();
  ASSERT_TRUE(resumed.result.has_value());
  EXPECT_TRUE(IsValidResult(mesh, *resumed.result));
  ASSERT_FALSE(sequences.empty());
  EXPECT_GE(sequences.front(), 1);
  const absl::StatusOr<v1::Job> done = client.GetJob(submitted->name(), v1::BASIC);
  ASSERT_TRUE(done.ok());
  EXPECT_EQ(done->state(), v1::SUCCEEDED);
}

TEST(JobLifecycleTest, EndingAQuantizeCallCancelsItsJob) {
  std::unique_ptr<ServerProcess> server = StartServerOrFail({"--workers=1"});
  ASSERT_NE(server, nullptr);
  client::QuantizerClient client = ClientOf(*server);
  const v1::TMesh& mesh = LongRunningMesh();
  // Stop at the first progress event: the job is running then.
  const client::JobOutcome outcome = client.Quantize(
      RequestFor(mesh, 100),
      StreamFor(kJobTimeout, [](const v1::QuantizeEvent& e) { return !e.has_progress(); }));
  EXPECT_EQ(outcome.status.code(), absl::StatusCode::kCancelled) << outcome.status;
  ASSERT_FALSE(outcome.job.empty());
  const absl::StatusOr<v1::Job> done = WaitUntilDone(client, outcome.job);
  ASSERT_TRUE(done.ok()) << done.status();
  EXPECT_EQ(done->state(), v1::CANCELLED);
  ASSERT_TRUE(done->has_result()) << "a job cancelled while running returns its best result";
  EXPECT_EQ(done->result().termination(), v1::INTERRUPTED);
  if (done->result().valid()) {
    EXPECT_TRUE(IsValidResult(mesh, done->result()));
  }
  EXPECT_TRUE(server->WaitForLog("event=job_end job=" + outcome.job + " state=CANCELLED"))
      << server->Log();
}

TEST(JobLifecycleTest, CancelJobInterruptsARunningJobAndWatchersGetItsResult) {
  std::unique_ptr<ServerProcess> server = StartServerOrFail({"--workers=1"});
  ASSERT_NE(server, nullptr);
  client::QuantizerClient client = ClientOf(*server);
  const v1::TMesh& mesh = LongRunningMesh();
  const absl::StatusOr<v1::Job> submitted = client.SubmitJob(RequestFor(mesh, 100));
  ASSERT_TRUE(submitted.ok()) << submitted.status();
  ASSERT_TRUE(WaitForState(client, submitted->name(), v1::RUNNING).ok());

  client::JobOutcome watched;
  absl::Notification watching;
  std::thread watcher([&] {
    watched = client.WatchJob(submitted->name(), 0,
                              StreamFor(kJobTimeout, [&](const v1::QuantizeEvent& event) {
                                if (event.has_accepted()) watching.Notify();
                                return true;
                              }));
  });
  watching.WaitForNotification();
  const absl::Time cancelled_at = absl::Now();
  const absl::StatusOr<v1::Job> cancel = client.CancelJob(submitted->name());
  ASSERT_TRUE(cancel.ok()) << cancel.status();
  EXPECT_TRUE(cancel->state() == v1::RUNNING || cancel->state() == v1::CANCELLED);
  watcher.join();
  // That the run stopped between LP solves rather than running to its end (about a minute)
  // shows in its INTERRUPTED result; how soon depends on the machine's load: reported only.
  std::cout << "the watcher had the result " << absl::FormatDuration(absl::Now() - cancelled_at)
            << " after the cancel\n";

  EXPECT_TRUE(watched.status.ok()) << watched.status;
  ASSERT_TRUE(watched.result.has_value());
  EXPECT_EQ(watched.result->termination(), v1::INTERRUPTED);
  if (watched.result->valid()) {
    EXPECT_TRUE(IsValidResult(mesh, *watched.result));
  }
  const absl::StatusOr<v1::Job> done = client.GetJob(submitted->name());
  ASSERT_TRUE(done.ok());
  EXPECT_EQ(done->state(), v1::CANCELLED);
}

TEST(JobLifecycleTest, CancelJobDropsAQueuedJob) {
  std::unique_ptr<ServerProcess> server = StartServerOrFail({"--workers=1"});
  ASSERT_NE(server, nullptr);
  client::QuantizerClient client = ClientOf(*server);
  const absl::StatusOr<v1::Job> running = client.SubmitJob(RequestFor(LongRunningMesh(), 100));
  ASSERT_TRUE(running.ok()) << running.status();
  const absl::StatusOr<v1::Job> queued = client.SubmitJob(RequestFor(NotchMesh(), 100));
  ASSERT_TRUE(queued.ok()) << queued.status();
  EXPECT_EQ(queued->state(), v1::QUEUED);

  const absl::StatusOr<v1::Job> cancel = client.CancelJob(queued->name());
  ASSERT_TRUE(cancel.ok()) << cancel.status();
  EXPECT_EQ(cancel->state(), v1::CANCELLED);
  EXPECT_TRUE(cancel->done());
  EXPECT_EQ(cancel->error().code(), static_cast<int>(absl::StatusCode::kCancelled));
  EXPECT_FALSE(cancel->has_start_time());

  const client::JobOutcome watched = client.WatchJob(queued->name(), 0, StreamFor(kJobTimeout));
  EXPECT_TRUE(watched.job_ended);
  EXPECT_EQ(watched.status.code(), absl::StatusCode::kCancelled) << watched.status;
  EXPECT_THAT(std::string(watched.status.message()), HasSubstr("cancelled while queued"));
  ASSERT_TRUE(client.CancelJob(running->name()).ok());
}

TEST(JobLifecycleTest, CancellingAFinishedJobChangesNothing) {
  std::unique_ptr<ServerProcess> server = StartServerOrFail({});
  ASSERT_NE(server, nullptr);
  client::QuantizerClient client = ClientOf(*server);
  const client::JobOutcome outcome =
      client.Quantize(RequestFor(NotchMesh(), 5), StreamFor(kJobTimeout));
  ASSERT_TRUE(outcome.status.ok()) << outcome.status;
  const absl::StatusOr<v1::Job> cancel = client.CancelJob(outcome.job);
  ASSERT_TRUE(cancel.ok()) << cancel.status();
  EXPECT_EQ(cancel->state(), v1::SUCCEEDED);
  EXPECT_TRUE(IsValidResult(NotchMesh(), cancel->result()));
}

TEST(JobLifecycleTest, FinishedJobsAreKeptWithinTheRetentionCount) {
  std::unique_ptr<ServerProcess> server = StartServerOrFail({"--retain_finished_jobs=2"});
  ASSERT_NE(server, nullptr);
  client::QuantizerClient client = ClientOf(*server);
  std::vector<std::string> jobs;
  for (int i = 0; i < 3; ++i) {
    const client::JobOutcome outcome =
        client.Quantize(RequestFor(NotchMesh(), 10), StreamFor(kJobTimeout));
    ASSERT_TRUE(outcome.status.ok()) << outcome.status;
    jobs.push_back(outcome.job);
  }
  const absl::StatusOr<v1::Job> oldest = client.GetJob(jobs[0]);
  EXPECT_EQ(oldest.status().code(), absl::StatusCode::kNotFound);
  EXPECT_THAT(std::string(oldest.status().message()), HasSubstr("not found"));
  EXPECT_TRUE(client.GetJob(jobs[1]).ok());
  EXPECT_TRUE(client.GetJob(jobs[2]).ok());
}

TEST(JobLifecycleTest, FinishedJobsAreKeptWithinTheRetentionTime) {
  constexpr absl::Duration kRetention = absl::Seconds(5);
  std::unique_ptr<ServerProcess> server =
      StartServerOrFail({absl::StrCat("--retain_seconds=", absl::ToInt64Seconds(kRetention))});
  ASSERT_NE(server, nullptr);
  client::QuantizerClient client = ClientOf(*server);
  // The job ends between `submitted` and `answered`: what the server must do at a given moment
  // follows from those two times alone, however slow the machine.
  const absl::Time submitted = absl::Now();
  const client::JobOutcome outcome =
      client.Quantize(RequestFor(NotchMesh(), 10), StreamFor(kJobTimeout));
  const absl::Time answered = absl::Now();
  ASSERT_TRUE(outcome.status.ok()) << outcome.status;
  const absl::StatusOr<v1::Job> kept = client.GetJob(outcome.job);
  if (absl::Now() - submitted < kRetention) {
    EXPECT_TRUE(kept.ok()) << kept.status();
  } else {
    std::cout << "too slow a machine to check that the job is kept: asked "
              << absl::FormatDuration(absl::Now() - submitted) << " after submitting\n";
  }
  absl::SleepFor(answered + kRetention + absl::Milliseconds(500) - absl::Now());
  EXPECT_EQ(client.GetJob(outcome.job).status().code(), absl::StatusCode::kNotFound);
}

TEST(JobLifecycleTest, ServerStatsCountJobsAndSolveTimes) {
  std::unique_ptr<ServerProcess> server = StartServerOrFail({"--workers=2", "--max_queued_jobs=7"});
  ASSERT_NE(server, nullptr);
  client::QuantizerClient client = ClientOf(*server);
  for (int level : {1, 50, 100}) {
    const client::JobOutcome outcome =
        client.Quantize(RequestFor(NotchMesh(), level), StreamFor(kJobTimeout));
    ASSERT_TRUE(outcome.status.ok()) << outcome.status;
  }
  const absl::StatusOr<v1::Job> queued_then_cancelled = client.SubmitJob(v1::QuantizeRequest());
  EXPECT_EQ(queued_then_cancelled.status().code(), absl::StatusCode::kInvalidArgument);

  // A worker counts its job (and itself as idle) just after publishing the result, so a client
  // that has the result may ask a moment too early on a loaded machine.
  absl::StatusOr<v1::ServerStats> stats = client.GetServerStats();
  for (const absl::Time deadline = absl::Now() + kSafetyNet;
       stats.ok() && stats->busy_workers() > 0 && absl::Now() < deadline;
       stats = client.GetServerStats()) {
    absl::SleepFor(absl::Milliseconds(10));
  }
  ASSERT_TRUE(stats.ok()) << stats.status();
  EXPECT_EQ(stats->workers(), 2);
  EXPECT_EQ(stats->max_queued_jobs(), 7);
  EXPECT_EQ(stats->queued_jobs(), 0);
  EXPECT_EQ(stats->busy_workers(), 0);
  EXPECT_EQ(stats->accepted_total(), 3);
  EXPECT_EQ(stats->rejected_invalid_total(), 1);
  EXPECT_EQ(stats->finished_total().succeeded(), 3);
  EXPECT_EQ(stats->retained_jobs().succeeded(), 3);
  EXPECT_EQ(stats->solve_seconds().count(), 3);
  EXPECT_GT(stats->solve_seconds().sum(), 0);
  ASSERT_GT(stats->solve_seconds().upper_bounds_size(), 0);
  EXPECT_EQ(stats->solve_seconds().upper_bounds_size(),
            stats->solve_seconds().cumulative_counts_size());
  EXPECT_EQ(stats->queue_wait_seconds().count(), 3);
  EXPECT_FALSE(stats->shutting_down());
  EXPECT_TRUE(stats->has_uptime());
}

}  // namespace
}  // namespace ispq::testing
