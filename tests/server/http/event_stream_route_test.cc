// SPDX-License-Identifier: Apache-2.0
// GET /v1/jobs/{id}:watch, the route called as the dispatcher calls it and its streamed body
// driven as libmicrohttpd drives it: the stream opens with the reconnect delay, writes each of
// the job's events as an SSE frame numbered by its sequence, parks while the job is silent and
// is resumed by its next event, and ends with the job's final status; where it starts follows
// Last-Event-ID before ?fromEvent; streams are bounded, give their slot back when they end, and
// end (for the client to reconnect elsewhere) once the server stops. Over a live server:
// tests/integration/http_event_stream_test.cc.
#include "server/http/event_stream_route.h"

#include <atomic>
#include <memory>
#include <string>
#include <utility>

#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "gmock/gmock.h"
#include "google/protobuf/struct.pb.h"
#include "gtest/gtest.h"
#include "server/http/event_streams.h"
#include "server/http/http_router.h"
#include "tests/server/http/http_test_service.h"

namespace ispq::server::http {
namespace {

using ::testing::HasSubstr;
using Step = StreamedBody::Step;

std::string Header(const HttpResponse& response, const std::string& name) {
  for (const auto& [key, value] : response.headers) {
    if (key == name) return value;
  }
  return "";
}

// The connection as the body sees it: counts its suspensions and resumes.
class CountingConnection : public StreamConnection {
 public:
  void Suspend() override { suspends.fetch_add(1); }
  void Resume() override { resumes.fetch_add(1); }
  std::atomic<int> suspends{0};
  std::atomic<int> resumes{0};
};

struct Produced {
  Step step;
  std::string out;
};

Produced ProduceOnce(StreamedBody& body, StreamConnection& connection) {
  Produced produced{.step = Step::kMore, .out = ""};
  produced.step = body.Produce(produced.out, connection);
  return produced;
}

// The event an "id: N\ndata: JSON\n\n" frame carries; fails the test for another frame.
v1::QuantizeEvent EventOf(const Produced& frame) {
  EXPECT_EQ(frame.step, Step::kMore);
  const size_t data = frame.out.find("\ndata: ");
  EXPECT_TRUE(absl::StartsWith(frame.out, "id: ") && data != std::string::npos &&
              absl::EndsWith(frame.out, "\n\n"))
      << frame.out;
  if (data == std::string::npos) return v1::QuantizeEvent();
  const v1::QuantizeEvent event =
      ParseJson<v1::QuantizeEvent>(frame.out.substr(data + 7, frame.out.size() - data - 9));
  EXPECT_EQ(frame.out.substr(4, data - 4), absl::StrCat(event.sequence()));
  return event;
}

class EventStreamRouteTest : public ::testing::Test {
 protected:
  static constexpr int kMaxStreams = 2;

  EventStreamRouteTest() : parts_(service_.parts()) {
    AddEventStreamRoute(router_, parts_, streams_);
  }

  // The route's answer to a watch of `job` (a name, "jobs/...") by `principal`.
  HttpResponse Watch(const std::string& job, const std::string& principal = "alice",
                     HttpFields query = {}, HttpFields headers = {}) {
    const std::string path = absl::StrCat("/v1/", job, ":watch");
    std::string id;
    const Route* route = router_.Match("GET", path, &id);
    EXPECT_NE(route, nullptr) << path;
    if (route == nullptr) return HttpResponse();
    HttpRequest request = RouteRequest("GET", path, id, principal);
    request.query = std::move(query);
    request.headers = std::move(headers);
    auto responder = std::make_shared<RecordingResponder>();
    route->handle(request, responder);
    EXPECT_EQ(responder->answers(), 1);
    return responder->WaitForAnswer();
  }

  // A stream of `job`, past its opening (the reconnect delay).
  std::unique_ptr<StreamedBody> OpenStream(const std::string& job, HttpFields query = {},
                                           HttpFields headers = {}) {
    HttpResponse response = Watch(job, "alice", std::move(query), std::move(headers));
    EXPECT_EQ(response.status, 200) << response.body;
    if (response.stream == nullptr) return nullptr;
    EXPECT_EQ(ProduceOnce(*response.stream, connection_).out, "retry: 1000\n\n");
    return std::move(response.stream);
  }

  void Cancel(const std::string& job) {
    v1::CancelJobRequest cancel;
    cancel.set_name(job);
    ASSERT_TRUE(service_.service.CancelJob(cancel, Principal{.name = "alice"}).ok());
  }

  HttpTestService service_;
  const HttpParts parts_;
  EventStreams streams_{kMaxStreams};
  Router router_;
  CountingConnection connection_;
};

TEST_F(EventStreamRouteTest, TheRouteAuthenticatesAndRunsOnTheLookupThreads) {
  std::string id;
  const Route* route = router_.Match("GET", "/v1/jobs/abc:watch", &id);
  ASSERT_NE(route, nullptr);
  EXPECT_EQ(id, "abc");
  EXPECT_TRUE(route->authenticated);
  EXPECT_EQ(route->lane, Lane::kLookup);
  EXPECT_FALSE(route->any_host);
  EXPECT_FALSE(route->takes_body);
}

TEST_F(EventStreamRouteTest, AStreamWritesTheJobsEventsAsTheyComeThenItsEnd) {
  const std::string job = service_.SubmitOrDie(NotchRequest(), "alice")->name();
  HttpResponse response = Watch(job);
  ASSERT_EQ(response.status, 200) << response.body;
  EXPECT_EQ(response.content_type, "text/event-stream");
  EXPECT_EQ(Header(response, "Cache-Control"), "no-cache");
  EXPECT_EQ(Header(response, "X-Accel-Buffering"), "no");
  ASSERT_NE(response.stream, nullptr);
  StreamedBody& stream = *response.stream;
  EXPECT_EQ(streams_.open_streams(), 1);

  const Produced opening = ProduceOnce(stream, connection_);
  EXPECT_EQ(opening.step, Step::kMore);
  EXPECT_EQ(opening.out, "retry: 1000\n\n");
  const v1::QuantizeEvent accepted = EventOf(ProduceOnce(stream, connection_));
  EXPECT_EQ(accepted.sequence(), 0);
  EXPECT_TRUE(accepted.has_accepted());

  // Nothing more while the job waits in the queue: the stream parks, writing nothing.
  const Produced silent = ProduceOnce(stream, connection_);
  EXPECT_EQ(silent.step, Step::kMore);
  EXPECT_EQ(silent.out, "");
  EXPECT_EQ(connection_.suspends.load(), 1);
  EXPECT_EQ(connection_.resumes.load(), 0);

  Cancel(job);  // the job's terminal event resumes the stream
  EXPECT_EQ(connection_.resumes.load(), 1);
  const v1::QuantizeEvent error = EventOf(ProduceOnce(stream, connection_));
  EXPECT_EQ(error.sequence(), 1);
  EXPECT_TRUE(error.has_error());
  const Produced end = ProduceOnce(stream, connection_);
  EXPECT_EQ(end.step, Step::kLast);
  ASSERT_TRUE(absl::StartsWith(end.out, "event: end\ndata: ")) << end.out;
  ASSERT_TRUE(absl::EndsWith(end.out, "\n\n")) << end.out;
  const auto status = ParseJson<google::protobuf::Struct>(end.out.substr(17, end.out.size() - 19));
  EXPECT_EQ(status.fields().at("status").string_value(), "CANCELLED");
  EXPECT_EQ(connection_.suspends.load(), 1);
}

// A reconnecting EventSource sends the last id it saw and must not get that event again.
TEST_F(EventStreamRouteTest, LastEventIdResumesAfterItAndTakesPrecedenceOverFromEvent) {
  const std::string job = service_.SubmitOrDie(NotchRequest(), "alice")->name();
  Cancel(job);  // events 0 (accepted) and 1 (the error)
  std::unique_ptr<StreamedBody> from_start = OpenStream(job);
  ASSERT_NE(from_start, nullptr);
  EXPECT_EQ(EventOf(ProduceOnce(*from_start, connection_)).sequence(), 0);
  from_start.reset();

  std::unique_ptr<StreamedBody> from_event = OpenStream(job, {{"fromEvent", "1"}});
  ASSERT_NE(from_event, nullptr);
  EXPECT_EQ(EventOf(ProduceOnce(*from_event, connection_)).sequence(), 1);
  from_event.reset();

  std::unique_ptr<StreamedBody> resumed =
      OpenStream(job, {{"fromEvent", "0"}}, {{"last-event-id", "0"}});
  ASSERT_NE(resumed, nullptr);
  EXPECT_EQ(EventOf(ProduceOnce(*resumed, connection_)).sequence(), 1);
  EXPECT_EQ(ProduceOnce(*resumed, connection_).step, Step::kLast);
  resumed.reset();

  // After the last event, only the end is left.
  std::unique_ptr<StreamedBody> done = OpenStream(job, {}, {{"last-event-id", "1"}});
  ASSERT_NE(done, nullptr);
  const Produced end = ProduceOnce(*done, connection_);
  EXPECT_EQ(end.step, Step::kLast);
  EXPECT_THAT(end.out, HasSubstr("event: end"));
}

TEST_F(EventStreamRouteTest, AWatchThatCannotStartIsAnError) {
  const std::string job = service_.SubmitOrDie(NotchRequest(), "alice")->name();
  for (const char* last : {"abc", "-1", "9223372036854775807", "1.5"}) {
    EXPECT_EQ(Watch(job, "alice", {}, {{"last-event-id", last}}).status, 400) << last;
  }
  for (const char* from : {"-2", "x"}) {
    EXPECT_EQ(Watch(job, "alice", {{"fromEvent", from}}).status, 400) << from;
  }
  EXPECT_EQ(Watch(job, "bob").status, 404);  // not bob's job: as if it did not exist
  EXPECT_EQ(Watch("jobs/0000000000000000").status, 404);
  const HttpResponse refused = Watch(job, "bob");
  EXPECT_EQ(refused.stream, nullptr);
  EXPECT_EQ(refused.content_type, "application/json");
  EXPECT_EQ(streams_.open_streams(), 0) << "a refused watch holds no stream";
  EXPECT_EQ(Watch(job, "admin").status, 200);
}

TEST_F(EventStreamRouteTest, StreamsAreBoundedAndGiveTheirSlotBackWhenTheyEnd) {
  const std::string job = service_.SubmitOrDie(NotchRequest(), "alice")->name();
  HttpResponse first = Watch(job);
  HttpResponse second = Watch(job);
  ASSERT_EQ(first.status, 200);
  ASSERT_EQ(second.status, 200);
  const HttpResponse third = Watch(job);
  EXPECT_EQ(third.status, 429);
  EXPECT_EQ(streams_.open_streams(), kMaxStreams);
  first.stream.reset();  // the connection closed: libmicrohttpd frees the body
  EXPECT_EQ(streams_.open_streams(), kMaxStreams - 1);
  EXPECT_EQ(Watch(job).status, 200);
}

// At shutdown a parked stream is woken and ends without the end event: its job has not ended,
// so its client should reconnect (to another replica) rather than give up.
TEST_F(EventStreamRouteTest, AStoppingServerEndsItsStreamsForTheClientsToReconnect) {
  const std::string job = service_.SubmitOrDie(NotchRequest(), "alice")->name();
  std::unique_ptr<StreamedBody> stream = OpenStream(job);
  ASSERT_NE(stream, nullptr);
  EXPECT_EQ(EventOf(ProduceOnce(*stream, connection_)).sequence(), 0);
  EXPECT_EQ(ProduceOnce(*stream, connection_).out, "");
  ASSERT_EQ(connection_.suspends.load(), 1);

  streams_.StopAll();
  EXPECT_EQ(connection_.resumes.load(), 1);
  const Produced last = ProduceOnce(*stream, connection_);
  EXPECT_EQ(last.step, Step::kAbort);
  EXPECT_EQ(last.out, "");
  EXPECT_EQ(Watch(job).status, 503);
}

}  // namespace
}  // namespace ispq::server::http
