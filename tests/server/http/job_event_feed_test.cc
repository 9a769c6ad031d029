// SPDX-License-Identifier: Apache-2.0
// The feed of a server-sent-event stream that no thread waits on: it hands the writer the job's
// events in order from where the stream starts, then the final status; a writer with nothing to
// write parks and is resumed by the job's next event, and an event that comes between the
// writer's last look and its parking is never missed (it would hang the stream).
#include "server/http/job_event_feed.h"

#include <cstdint>
#include <memory>
#include <vector>

#include "absl/status/status.h"
#include "absl/time/clock.h"
#include "gtest/gtest.h"
#include "tests/server/server_test_jobs.h"

namespace ispq::server::http {
namespace {

v1::Progress ProgressAt(int64_t lp_solves) {
  v1::Progress progress;
  progress.set_lp_solves(lp_solves);
  return progress;
}

// What a stream's writer sees of its connection.
struct ParkCounts {
  int suspends = 0;
  int resumes = 0;
};

bool ParkCounting(JobEventFeed& feed, ParkCounts& counts) {
  return feed.Park([&counts] { ++counts.suspends; }, [&counts] { ++counts.resumes; });
}

TEST(JobEventFeedTest, HandsOverTheEventsInOrderThenTheFinalStatus) {
  const std::shared_ptr<Job> job = NewNotchJob("feed-order");
  JobEventFeed feed(job, 0);
  Job::StreamStep step = feed.Next();
  ASSERT_TRUE(step.event.has_value());
  EXPECT_EQ(step.event->sequence(), 0);  // accepted
  step = feed.Next();
  EXPECT_FALSE(step.event.has_value());
  EXPECT_FALSE(step.final_status.has_value());  // nothing yet, and not ended

  ASSERT_TRUE(job->Start(absl::Now()));
  job->PublishProgress(ProgressAt(1));
  job->PublishProgress(ProgressAt(2));
  job->FinishWithError(absl::CancelledError("stopped"), absl::Now());
  std::vector<int64_t> sequences;
  while (true) {
    step = feed.Next();
    if (!step.event.has_value()) break;
    sequences.push_back(step.event->sequence());
  }
  // The second progress supersedes the first (the log keeps the latest), then the error.
  EXPECT_EQ(sequences, (std::vector<int64_t>{2, 3}));
  ASSERT_TRUE(step.final_status.has_value());
  EXPECT_EQ(step.final_status->code(), absl::StatusCode::kCancelled);
  // The end is stable: asking again gives it again, no event.
  step = feed.Next();
  EXPECT_FALSE(step.event.has_value());
  EXPECT_TRUE(step.final_status.has_value());
}

TEST(JobEventFeedTest, StartsAtTheRequestedEvent) {
  const std::shared_ptr<Job> job = NewNotchJob("feed-from");
  ASSERT_TRUE(job->Start(absl::Now()));
  job->PublishProgress(ProgressAt(1));
  job->PublishIntermediate(v1::IntermediateQuantization());
  JobEventFeed from_intermediate(job, 2);
  Job::StreamStep step = from_intermediate.Next();
  ASSERT_TRUE(step.event.has_value());
  EXPECT_EQ(step.event->sequence(), 2);
  EXPECT_TRUE(step.event->has_intermediate());
  EXPECT_FALSE(from_intermediate.Next().event.has_value());

  JobEventFeed from_progress(job, 1);
  step = from_progress.Next();
  ASSERT_TRUE(step.event.has_value());
  EXPECT_EQ(step.event->sequence(), 1);
  EXPECT_EQ(step.event->progress().lp_solves(), 1);
  step = from_progress.Next();
  ASSERT_TRUE(step.event.has_value());
  EXPECT_EQ(step.event->sequence(), 2);
}

TEST(JobEventFeedTest, AParkedWriterIsResumedOnceByTheJobsNextEvent) {
  const std::shared_ptr<Job> job = NewNotchJob("feed-park");
  const std::shared_ptr<JobEventFeed> feed = JobEventFeed::Watch(job, 0);
  ASSERT_TRUE(feed->Next().event.has_value());
  ASSERT_FALSE(feed->Next().event.has_value());
  ParkCounts counts;
  ASSERT_TRUE(ParkCounting(*feed, counts));
  EXPECT_EQ(counts.suspends, 1);
  EXPECT_EQ(counts.resumes, 0);

  ASSERT_TRUE(job->Start(absl::Now()));
  job->PublishProgress(ProgressAt(1));  // the feed watches the job: this wakes it
  EXPECT_EQ(counts.resumes, 1);
  job->PublishProgress(ProgressAt(2));  // not parked any more: no second resume
  feed->Wake();
  EXPECT_EQ(counts.resumes, 1);

  Job::StreamStep step = feed->Next();
  ASSERT_TRUE(step.event.has_value());
  EXPECT_EQ(step.event->sequence(), 2);  // the latest progress, which superseded the first
}

// The writer looked (nothing), then the job appended and woke the feed, then the writer parks:
// parking must refuse, so that the writer looks again instead of sleeping past the event.
TEST(JobEventFeedTest, AWakeBetweenNextAndParkIsNotMissed) {
  const std::shared_ptr<Job> job = NewNotchJob("feed-race");
  const std::shared_ptr<JobEventFeed> feed = JobEventFeed::Watch(job, 1);
  EXPECT_FALSE(feed->Next().event.has_value());
  ASSERT_TRUE(job->Start(absl::Now()));
  job->PublishProgress(ProgressAt(1));
  ParkCounts counts;
  EXPECT_FALSE(ParkCounting(*feed, counts));
  EXPECT_EQ(counts.suspends, 0);
  Job::StreamStep step = feed->Next();
  ASSERT_TRUE(step.event.has_value());
  EXPECT_EQ(step.event->sequence(), 1);

  // Once it has looked again, with nothing new, it parks; a server wake (keepalive, shutdown)
  // resumes it as an event does.
  EXPECT_FALSE(feed->Next().event.has_value());
  EXPECT_TRUE(ParkCounting(*feed, counts));
  feed->Wake();
  EXPECT_EQ(counts.suspends, 1);
  EXPECT_EQ(counts.resumes, 1);
}

// A stream may start on a job that has ended: it is woken at once to write the job's events.
TEST(JobEventFeedTest, WatchingAnEndedJobWakesTheWriterAtOnce) {
  const std::shared_ptr<Job> job = NewNotchJob("feed-ended");
  job->FinishWithError(absl::CancelledError("before it ran"), absl::Now());
  const std::shared_ptr<JobEventFeed> feed = JobEventFeed::Watch(job, 0);
  ParkCounts counts;
  EXPECT_FALSE(ParkCounting(*feed, counts));  // before any Next: the watch's wake is pending
  Job::StreamStep step = feed->Next();
  ASSERT_TRUE(step.event.has_value());
  EXPECT_EQ(step.event->sequence(), 0);
}

}  // namespace
}  // namespace ispq::server::http
