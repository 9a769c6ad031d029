// SPDX-License-Identifier: Apache-2.0
#include "server/http/event_streams.h"

#include <atomic>
#include <memory>
#include <vector>

#include "absl/status/status.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "server/http/job_event_feed.h"
#include "server/jobs/retry_hint.h"
#include "tests/server/server_test_jobs.h"

namespace ispq::server::http {
namespace {

using ::testing::HasSubstr;

// Reads `feed` up to what the job has and parks it, as a stream's writer with nothing to write
// does; `resumed` counts the wakeups that reach it.
void ReadAllAndPark(JobEventFeed& feed, std::atomic<int>& resumed) {
  while (feed.Next().event.has_value()) {
  }
  ASSERT_TRUE(feed.Park([] {}, [&resumed] { ++resumed; }));
}

TEST(EventStreamsTest, OpensAFeedFromTheGivenEvent) {
  EventStreams streams(4);
  const std::shared_ptr<Job> job = NewNotchJob("a");
  const absl::StatusOr<std::shared_ptr<JobEventFeed>> feed = streams.Open(job, 0);
  ASSERT_TRUE(feed.ok()) << feed.status();
  EXPECT_EQ(streams.open_streams(), 1);
  const Job::StreamStep first = (*feed)->Next();
  ASSERT_TRUE(first.event.has_value());
  EXPECT_EQ(first.event->sequence(), 0);
  EXPECT_TRUE(first.event->has_accepted());
  const absl::StatusOr<std::shared_ptr<JobEventFeed>> later = streams.Open(job, 1);
  ASSERT_TRUE(later.ok());
  EXPECT_FALSE((*later)->Next().event.has_value());  // nothing from event 1 on yet
}

// Each stream holds a watcher, a connection and bytes in flight: past the bound, a watcher is
// told to come back later (429 with Retry-After) or to use gRPC.
TEST(EventStreamsTest, RefusesStreamsBeyondTheBoundUntilOneCloses) {
  EventStreams streams(2);
  const std::shared_ptr<Job> job = NewNotchJob("a");
  const auto first = streams.Open(job, 0);
  const auto second = streams.Open(job, 0);
  ASSERT_TRUE(first.ok());
  ASSERT_TRUE(second.ok());
  const auto third = streams.Open(job, 0);
  ASSERT_FALSE(third.ok());
  EXPECT_EQ(third.status().code(), absl::StatusCode::kResourceExhausted);
  EXPECT_THAT(third.status().message(), HasSubstr("too many event streams are open (2)"));
  EXPECT_TRUE(RetryHintOf(third.status()).has_value());
  EXPECT_EQ(streams.open_streams(), 2);

  streams.Close(*first);
  EXPECT_EQ(streams.open_streams(), 1);
  EXPECT_TRUE(streams.Open(job, 0).ok());
  EXPECT_EQ(streams.open_streams(), 2);
}

// Keepalives: every open stream is woken, whether or not its job has anything new; a closed
// one is not.
TEST(EventStreamsTest, WakeAllResumesEveryParkedStream) {
  EventStreams streams(4);
  const std::shared_ptr<Job> job = NewNotchJob("a");
  const auto open = streams.Open(job, 0);
  const auto closed = streams.Open(job, 0);
  ASSERT_TRUE(open.ok());
  ASSERT_TRUE(closed.ok());
  std::atomic<int> open_resumed = 0;
  std::atomic<int> closed_resumed = 0;
  ReadAllAndPark(**open, open_resumed);
  ReadAllAndPark(**closed, closed_resumed);
  streams.Close(*closed);

  streams.WakeAll();
  EXPECT_EQ(open_resumed, 1);
  EXPECT_EQ(closed_resumed, 0);
  EXPECT_FALSE(streams.stopping());
}

TEST(EventStreamsTest, StopAllWakesTheOpenStreamsAndRefusesNewOnes) {
  EventStreams streams(4);
  const std::shared_ptr<Job> job = NewNotchJob("a");
  std::vector<std::shared_ptr<JobEventFeed>> feeds;
  std::atomic<int> resumed[3] = {0, 0, 0};
  for (std::atomic<int>& count : resumed) {
    auto feed = streams.Open(job, 0);
    ASSERT_TRUE(feed.ok());
    ReadAllAndPark(**feed, count);
    feeds.push_back(*std::move(feed));
  }
  streams.StopAll();
  EXPECT_TRUE(streams.stopping());
  for (const std::atomic<int>& count : resumed) EXPECT_EQ(count, 1);

  const auto refused = streams.Open(job, 0);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.status().code(), absl::StatusCode::kUnavailable);
  // The woken streams end and close themselves.
  for (const auto& feed : feeds) streams.Close(feed);
  EXPECT_EQ(streams.open_streams(), 0);
}

}  // namespace
}  // namespace ispq::server::http
