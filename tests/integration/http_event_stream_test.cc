// SPDX-License-Identifier: Apache-2.0
// Job events as server-sent events (GET /v1/jobs/{id}:watch, server/http/event_stream_route.h)
// against a live server: the same events as gRPC's WatchJob for the same job, `id:` the event
// number, resuming after Last-Event-ID, an `end` frame with the final status, a bound on the
// number of open streams, and the job's last events written before the server stops.
#include <signal.h>

#include <string>
#include <thread>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/synchronization/mutex.h"
#include "absl/time/clock.h"
#include "gmock/gmock.h"
#include "google/protobuf/util/message_differencer.h"
#include "gtest/gtest.h"
#include "tests/integration/http_test_support.h"
#include "tests/integration/service_test_support.h"
#include "tests/support/bounded_wait.h"

namespace ispq::testing {
namespace {

using ::google::protobuf::util::MessageDifferencer;
using ::testing::HasSubstr;

std::string WatchPath(const std::string& job, const std::string& query = "") {
  return absl::StrCat("/v1/", job, ":watch", query);
}

// Every event of a gRPC WatchJob from `from_event`.
std::vector<v1::QuantizeEvent> GrpcEvents(client::QuantizerClient& client, const std::string& job,
                                          int64_t from_event, client::JobOutcome* outcome) {
  std::vector<v1::QuantizeEvent> events;
  *outcome = client.WatchJob(job, from_event, StreamFor(kJobTimeout, [&](const auto& event) {
                               events.push_back(event);
                               return true;
                             }));
  return events;
}

void ExpectSameEvents(const std::vector<v1::QuantizeEvent>& sse,
                      const std::vector<v1::QuantizeEvent>& grpc) {
  ASSERT_EQ(sse.size(), grpc.size());
  for (size_t i = 0; i < sse.size(); ++i) {
    EXPECT_TRUE(MessageDifferencer::Equals(sse[i], grpc[i]))
        << "event " << i << ":\n"
        << sse[i].ShortDebugString() << "\nvs\n"
        << grpc[i].ShortDebugString();
  }
}

// Two readers of a running job: the log keeps only the latest progress and intermediate snapshot
// (server/model/job_event_log.h), so a reader that falls behind, as one may on a loaded machine,
// skips superseded snapshots. Every event both received is the same, and each skipped one is a
// snapshot; the accepted event and the result reach both.
void ExpectAgreeingLiveEvents(const std::vector<v1::QuantizeEvent>& sse,
                              const std::vector<v1::QuantizeEvent>& grpc) {
  const auto is_snapshot = [](const v1::QuantizeEvent& e) {
    return e.has_progress() || e.has_intermediate();
  };
  size_t i = 0, j = 0, common = 0;
  while (i < sse.size() || j < grpc.size()) {
    if (j == grpc.size() || (i < sse.size() && sse[i].sequence() < grpc[j].sequence())) {
      EXPECT_TRUE(is_snapshot(sse[i])) << "only in the SSE stream: " << sse[i].ShortDebugString();
      ++i;
    } else if (i == sse.size() || grpc[j].sequence() < sse[i].sequence()) {
      EXPECT_TRUE(is_snapshot(grpc[j])) << "only in WatchJob: " << grpc[j].ShortDebugString();
      ++j;
    } else {
      EXPECT_TRUE(MessageDifferencer::Equals(sse[i], grpc[j]))
          << "event " << sse[i].sequence() << ":\n"
          << sse[i].ShortDebugString() << "\nvs\n"
          << grpc[j].ShortDebugString();
      ++i, ++j, ++common;
    }
  }
  EXPECT_GE(common, 2u) << "the accepted event and the result at least";
}

// The frames' ids are the events' numbers, and the stream ends with an `end` frame.
void ExpectWellFormed(const SseStream& stream, const std::string& final_status) {
  EXPECT_EQ(stream.status, 200);
  EXPECT_THAT(stream.content_type, HasSubstr("text/event-stream"));
  ASSERT_FALSE(stream.frames.empty());
  for (const SseFrame& frame : stream.frames) {
    if (!frame.event.empty()) continue;
    EXPECT_EQ(frame.id, absl::StrCat(FromJson<v1::QuantizeEvent>(frame.data).sequence()));
  }
  EXPECT_EQ(stream.frames.back().event, "end");
  EXPECT_THAT(stream.frames.back().data, HasSubstr(absl::StrCat("\"", final_status, "\"")));
}

TEST(HttpEventStreamTest, FinishedJobStreamsTheSameEventsAsWatchJob) {
  HttpServer server = StartHttpServerOrFail({"--workers=1"});
  ASSERT_NE(server.process, nullptr);
  client::QuantizerClient client = ClientOf(*server.process);
  const v1::TMesh mesh = MeshTakingSeconds(0.3);
  v1::QuantizeRequest request = RequestFor(mesh, 100);
  request.mutable_intermediate_interval()->set_nanos(20'000'000);
  const absl::StatusOr<v1::Job> job = client.SubmitJob(request);
  ASSERT_TRUE(job.ok()) << job.status();
  ASSERT_TRUE(WaitUntilDone(client, job->name()).ok());

  for (const int64_t from : {0, 1, 2}) {
    client::JobOutcome outcome;
    const std::vector<v1::QuantizeEvent> grpc = GrpcEvents(client, job->name(), from, &outcome);
    ASSERT_TRUE(outcome.status.ok()) << outcome.status;
    const SseStream stream = ReadEventStream(
        server.http_port, WatchPath(job->name(), absl::StrCat("?fromEvent=", from)));
    ExpectWellFormed(stream, "OK");
    ExpectSameEvents(EventsOf(stream), grpc);
  }
  // Last-Event-ID n resumes at n + 1, as WatchJob(from_event = n + 1).
  client::JobOutcome outcome;
  const std::vector<v1::QuantizeEvent> grpc = GrpcEvents(client, job->name(), 1, &outcome);
  const SseStream resumed = ReadEventStream(server.http_port, WatchPath(job->name()), "0");
  ExpectWellFormed(resumed, "OK");
  ExpectSameEvents(EventsOf(resumed), grpc);
  ASSERT_FALSE(grpc.empty());
  ASSERT_TRUE(grpc.back().has_result());
  EXPECT_TRUE(IsValidResult(mesh, grpc.back().result()));

  const SseStream bad = ReadEventStream(server.http_port, WatchPath(job->name()), "seven");
  EXPECT_EQ(bad.status, 400);
}

TEST(HttpEventStreamTest, LiveJobStreamsTheSameEventsAsWatchJob) {
  HttpServer server = StartHttpServerOrFail({"--workers=1"});
  ASSERT_NE(server.process, nullptr);
  client::QuantizerClient client = ClientOf(*server.process);
  const v1::TMesh mesh = MeshTakingSeconds(2);
  v1::QuantizeRequest request = RequestFor(mesh, 100);
  request.mutable_progress_interval()->set_nanos(20'000'000);
  request.mutable_intermediate_interval()->set_nanos(100'000'000);
  const HttpAnswer submitted = HttpPost(server.http_port, "/v1/jobs", RequestJson(request));
  ASSERT_EQ(submitted.status, 200) << submitted.body;
  const std::string name = FromJson<v1::Job>(submitted.body).name();

  // Both watch from the start while the job runs.
  SseStream stream;
  std::thread sse([&] { stream = ReadEventStream(server.http_port, WatchPath(name)); });
  client::JobOutcome outcome;
  const std::vector<v1::QuantizeEvent> grpc = GrpcEvents(client, name, 0, &outcome);
  sse.join();
  ASSERT_TRUE(outcome.status.ok()) << outcome.status;
  ExpectWellFormed(stream, "OK");
  const std::vector<v1::QuantizeEvent> events = EventsOf(stream);
  ASSERT_GE(events.size(), 4u) << "accepted, progress..., result";
  ExpectAgreeingLiveEvents(events, grpc);
  EXPECT_TRUE(events.front().has_accepted());
  ASSERT_TRUE(events.back().has_result());
  EXPECT_TRUE(IsValidResult(mesh, events.back().result()));
}

TEST(HttpEventStreamTest, ResumesAfterABrokenConnection) {
  HttpServer server = StartHttpServerOrFail({"--workers=1"});
  ASSERT_NE(server.process, nullptr);
  client::QuantizerClient client = ClientOf(*server.process);
  const v1::TMesh mesh = MeshTakingSeconds(2);
  v1::QuantizeRequest request = RequestFor(mesh, 100);
  request.mutable_progress_interval()->set_nanos(50'000'000);
  const absl::StatusOr<v1::Job> job = client.SubmitJob(request);
  ASSERT_TRUE(job.ok()) << job.status();

  // Two events (accepted and the first progress), then the client hangs up; it comes back with
  // the last id it saw.
  const SseStream first = ReadEventStream(server.http_port, WatchPath(job->name()), "", "", 2);
  const std::vector<v1::QuantizeEvent> before = EventsOf(first);
  ASSERT_FALSE(before.empty());
  const int64_t last = before.back().sequence();
  const SseStream second =
      ReadEventStream(server.http_port, WatchPath(job->name()), absl::StrCat(last));
  ExpectWellFormed(second, "OK");
  const std::vector<v1::QuantizeEvent> after = EventsOf(second);
  ASSERT_FALSE(after.empty());
  EXPECT_GT(after.front().sequence(), last);
  ASSERT_TRUE(after.back().has_result());
  EXPECT_TRUE(IsValidResult(mesh, after.back().result()));
}

TEST(HttpEventStreamTest, OpenStreamsAreBounded) {
  HttpServer server = StartHttpServerOrFail({"--workers=1", "--http_max_event_streams=1"});
  ASSERT_NE(server.process, nullptr);
  client::QuantizerClient client = ClientOf(*server.process);
  const absl::StatusOr<v1::Job> job = client.SubmitJob(RequestFor(LongRunningMesh(), 100));
  ASSERT_TRUE(job.ok()) << job.status();
  ASSERT_TRUE(WaitForState(client, job->name(), v1::RUNNING).ok());

  SseStream held;
  std::thread holder([&] { held = ReadEventStream(server.http_port, WatchPath(job->name())); });
  // Once the holder's stream is open (as /metrics counts it), a second one is refused. Bounded
  // only against a hang: the second stream must not be tried before the first is open.
  const absl::Time deadline = absl::Now() + kSafetyNet;
  while (HttpGet(server.http_port, "/metrics").body.find("\nispq_http_event_streams 1\n") ==
             std::string::npos &&
         absl::Now() < deadline) {
    absl::SleepFor(absl::Milliseconds(20));
  }
  const SseStream refused = ReadEventStream(server.http_port, WatchPath(job->name()));
  EXPECT_EQ(refused.status, 429);
  ASSERT_FALSE(refused.frames.empty());
  EXPECT_THAT(refused.frames.back().data, HasSubstr("too many event streams"));

  ASSERT_TRUE(client.CancelJob(job->name()).ok());
  holder.join();
  ExpectWellFormed(held, "OK");  // a cancelled job that ran ends with its best result
  const std::vector<v1::QuantizeEvent> events = EventsOf(held);
  ASSERT_FALSE(events.empty());
  if (events.back().has_result() && events.back().result().valid()) {
    EXPECT_TRUE(IsValidResult(LongRunningMesh(), events.back().result()));
  }
  // The slot is free again.
  EXPECT_EQ(ReadEventStream(server.http_port, WatchPath(job->name())).status, 200);
}

// At SIGTERM the running job is interrupted near the end of the grace period; its stream, which
// no thread waits on, is woken by the job's last event and writes it and the `end` frame before
// the HTTP side stops. The grace period gives interrupted jobs the full window a deployment gets
// (5 s; see ShutdownTest.TheEndOfTheGracePeriodInterruptsRunningJobsAndDeliversTheirResults).
TEST(HttpEventStreamTest, StreamsEndWithTheirJobsLastEventsAtShutdown) {
  HttpServer server = StartHttpServerOrFail({"--workers=1", "--shutdown_grace_seconds=20"});
  ASSERT_NE(server.process, nullptr);
  client::QuantizerClient client = ClientOf(*server.process);
  const absl::StatusOr<v1::Job> job = client.SubmitJob(RequestFor(LongRunningMesh(), 100));
  ASSERT_TRUE(job.ok()) << job.status();
  ASSERT_TRUE(WaitForState(client, job->name(), v1::RUNNING).ok());

  SseStream stream;
  std::thread reader([&] { stream = ReadEventStream(server.http_port, WatchPath(job->name())); });
  const absl::Time deadline = absl::Now() + absl::Seconds(30);
  while (HttpGet(server.http_port, "/metrics").body.find("\nispq_http_event_streams 1\n") ==
             std::string::npos &&
         absl::Now() < deadline) {
    absl::SleepFor(absl::Milliseconds(20));
  }
  server.process->Signal(SIGTERM);
  reader.join();
  EXPECT_EQ(server.process->WaitForExit(absl::Seconds(60)), 0);

  EXPECT_EQ(stream.status, 200);
  ASSERT_GE(stream.frames.size(), 2u);
  EXPECT_EQ(stream.frames.back().event, "end");
  const std::vector<v1::QuantizeEvent> events = EventsOf(stream);
  ASSERT_FALSE(events.empty());
  EXPECT_TRUE(events.back().has_result() || events.back().has_error())
      << events.back().ShortDebugString();
}

}  // namespace
}  // namespace ispq::testing
