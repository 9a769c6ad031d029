#include "server/http/event_stream_route.h"

#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <utility>

#include "absl/status/status.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/time/clock.h"
#include "absl/time/time.h"
#include "server/http/http_exchange.h"
#include "server/http/http_status.h"
#include "server/http/proto_json.h"
#include "server/http/query_params.h"
#include "server/resource_names.h"

namespace ispq::server::http {
namespace {

// Silence longer than this gets a comment line, so that a vanished client is noticed.
constexpr absl::Duration kKeepaliveInterval = absl::Seconds(15);
// How often a waiting stream looks at the server's stopping flag.
constexpr absl::Duration kWakeInterval = absl::Seconds(1);
// What an EventSource waits before reconnecting after a broken connection.
constexpr char kRetryField[] = "retry: 1000\n\n";

std::string EventFrame(const v1::QuantizeEvent& event) {
  return absl::StrCat("id: ", event.sequence(), "\ndata: ", ToJson(event), "\n\n");
}

std::string EndFrame(const absl::Status& status) {
  return absl::StrCat("event: end\ndata: ", ErrorJson(status), "\n\n");
}

// The first event to send: after Last-Event-ID if the client sends one, else ?fromEvent.
absl::StatusOr<int64_t> FirstEvent(const httplib::Request& request) {
  const std::string last = request.get_header_value("Last-Event-ID");
  if (last.empty()) {
    return IntParam(request, "fromEvent", 0, 0, std::numeric_limits<int64_t>::max());
  }
  int64_t sequence = 0;
  if (!absl::SimpleAtoi(last, &sequence) || sequence < 0 ||
      sequence == std::numeric_limits<int64_t>::max()) {
    return absl::InvalidArgumentError(
        absl::StrCat("Last-Event-ID ", last, " is not an event number of this stream"));
  }
  return sequence + 1;
}

// One stream: writes what the feed has, as it comes.
class EventWriter {
 public:
  EventWriter(std::shared_ptr<JobEventFeed> feed, EventStreams& streams, MemoryBudget& budget)
      : feed_(std::move(feed)), streams_(streams), budget_(budget) {}

  // cpp-httplib's content provider: writes at most one frame per call and returns whether the
  // stream goes on (false aborts the connection; done() ends it cleanly).
  bool Provide(httplib::DataSink& sink) {
    if (!started_) {
      started_ = true;
      return Write(sink, kRetryField);
    }
    while (true) {
      if (!sink.is_writable()) return false;
      const Job::StreamStep step = feed_->Next(absl::Now() + kWakeInterval);
      if (step.event.has_value()) return Write(sink, EventFrame(*step.event));
      if (step.final_status.has_value()) {
        const bool written = Write(sink, EndFrame(*step.final_status));
        sink.done();
        return written;
      }
      if (streams_.stopping()) return false;  // the client reconnects to a live server
      if (absl::Now() - last_write_ >= kKeepaliveInterval) return Write(sink, ": keepalive\n\n");
    }
  }

 private:
  bool Write(httplib::DataSink& sink, const std::string& frame) {
    // Accounted while it is written, as the event a gRPC stream has in flight.
    MemoryReservation in_flight =
        budget_.ForceReserve(MemoryUse::kResponses, static_cast<int64_t>(frame.size()));
    last_write_ = absl::Now();
    return sink.write(frame.data(), frame.size());
  }

  const std::shared_ptr<JobEventFeed> feed_;
  EventStreams& streams_;
  MemoryBudget& budget_;
  bool started_ = false;
  absl::Time last_write_ = absl::Now();
};

void WatchJob(const HttpParts& parts, EventStreams& streams, const httplib::Request& request,
              httplib::Response& response) {
  absl::StatusOr<Principal> principal = AuthenticateRequest(request, parts.authenticator);
  if (!principal.ok()) return ReplyError(response, principal.status());
  absl::StatusOr<int64_t> from_event = FirstEvent(request);
  if (!from_event.ok()) return ReplyError(response, from_event.status());
  v1::WatchJobRequest watch;
  watch.set_name(absl::StrCat(kJobCollection, "/", request.matches[1].str()));
  watch.set_from_event(*from_event);
  absl::StatusOr<WatchTarget> target = parts.service.Watch(watch, *principal);
  if (!target.ok()) return ReplyError(response, target.status());
  absl::StatusOr<std::shared_ptr<JobEventFeed>> feed =
      streams.Open(std::move(target->job), target->from_event);
  if (!feed.ok()) return ReplyError(response, feed.status());

  auto writer = std::make_shared<EventWriter>(*feed, streams, parts.memory.budget());
  response.set_header("Cache-Control", "no-cache");
  response.set_header("X-Accel-Buffering", "no");  // proxies: do not hold events back
  response.set_chunked_content_provider(
      "text/event-stream",
      [writer](size_t /*offset*/, httplib::DataSink& sink) { return writer->Provide(sink); },
      [&streams, feed = *feed](bool /*success*/) { streams.Close(feed); });
}

}  // namespace

void AddEventStreamRoute(httplib::Server& server, const HttpParts& parts, EventStreams& streams) {
  server.Get("/v1/jobs/([^/:]+):watch",
             [&parts, &streams](const httplib::Request& request, httplib::Response& response) {
               WatchJob(parts, streams, request, response);
             });
}

}  // namespace ispq::server::http
