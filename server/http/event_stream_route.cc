// SPDX-License-Identifier: Apache-2.0
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
#include "server/model/resource_names.h"

namespace ispq::server::http {
namespace {

// Silence longer than this gets a comment line, so that a vanished client is noticed.
constexpr absl::Duration kKeepaliveInterval = absl::Seconds(15);
// What an EventSource waits before reconnecting after a broken connection.
constexpr char kRetryField[] = "retry: 1000\n\n";
constexpr char kKeepalive[] = ": keepalive\n\n";

std::string EventFrame(const v1::QuantizeEvent& event) {
  return absl::StrCat("id: ", event.sequence(), "\ndata: ", ToJson(event), "\n\n");
}

std::string EndFrame(const absl::Status& status) {
  return absl::StrCat("event: end\ndata: ", ErrorJson(status), "\n\n");
}

// The first event to send: after Last-Event-ID if the client sends one, else ?fromEvent.
absl::StatusOr<int64_t> FirstEvent(const HttpRequest& request) {
  const std::string last(request.Header("last-event-id"));
  if (last.empty()) {
    return IntParam(request, "fromEvent", 0, 0, std::numeric_limits<int64_t>::max());
  }
  int64_t sequence = 0;
  if (!absl::SimpleAtoi(last, &sequence) || sequence < 0 ||
      sequence == std::numeric_limits<int64_t>::max()) {
    return absl::InvalidArgumentError(absl::StrCat("Last-Event-ID ", last.substr(0, 100),
                                                   " is not an event number of this stream"));
  }
  return sequence + 1;
}

// One stream: writes what the feed has, as it comes, one frame at a time; parks when there is
// nothing to write.
class EventWriter : public StreamedBody {
 public:
  EventWriter(std::shared_ptr<JobEventFeed> feed, EventStreams& streams)
      : feed_(std::move(feed)), streams_(streams) {}
  ~EventWriter() override { streams_.Close(feed_); }

  Step Produce(std::string& out, StreamConnection& connection) override {
    if (!started_) {
      started_ = true;
      return Write(kRetryField, out);
    }
    while (true) {
      const Job::StreamStep step = feed_->Next();
      if (step.event.has_value()) return Write(EventFrame(*step.event), out);
      if (step.final_status.has_value()) {
        out = EndFrame(*step.final_status);
        return Step::kLast;
      }
      if (streams_.stopping()) return Step::kAbort;  // the client reconnects to a live server
      if (absl::Now() - last_write_ >= kKeepaliveInterval) return Write(kKeepalive, out);
      if (feed_->Park([&connection] { connection.Suspend(); },
                      [&connection] { connection.Resume(); })) {
        return Step::kMore;  // nothing written: asked again once resumed
      }
    }
  }

 private:
  Step Write(std::string frame, std::string& out) {
    last_write_ = absl::Now();
    out = std::move(frame);
    return Step::kMore;
  }

  const std::shared_ptr<JobEventFeed> feed_;
  EventStreams& streams_;
  bool started_ = false;
  absl::Time last_write_ = absl::Now();
};

void WatchJob(const HttpParts& parts, EventStreams& streams, HttpRequest& request,
              const std::shared_ptr<Responder>& responder) {
  absl::StatusOr<int64_t> from_event = FirstEvent(request);
  if (!from_event.ok()) return responder->Answer(ErrorResponse(from_event.status()));
  v1::WatchJobRequest watch;
  watch.set_name(absl::StrCat(kJobCollection, "/", request.id));
  watch.set_from_event(*from_event);
  absl::StatusOr<WatchTarget> target = parts.service.Watch(watch, request.principal);
  if (!target.ok()) return responder->Answer(ErrorResponse(target.status()));
  absl::StatusOr<std::shared_ptr<JobEventFeed>> feed =
      streams.Open(std::move(target->job), target->from_event);
  if (!feed.ok()) return responder->Answer(ErrorResponse(feed.status()));

  HttpResponse response;
  response.content_type = "text/event-stream";
  response.headers.emplace_back("Cache-Control", "no-cache");
  response.headers.emplace_back("X-Accel-Buffering", "no");  // proxies: do not hold events back
  response.stream = std::make_unique<EventWriter>(*std::move(feed), streams);
  responder->Answer(std::move(response));
}

}  // namespace

void AddEventStreamRoute(Router& router, const HttpParts& parts, EventStreams& streams) {
  Route route;
  route.method = "GET";
  route.pattern = "/v1/jobs/{id}:watch";
  route.lane = Lane::kLookup;
  route.authenticated = true;
  route.handle = [&parts, &streams](HttpRequest& request,
                                    const std::shared_ptr<Responder>& responder) {
    WatchJob(parts, streams, request, responder);
  };
  router.Add(std::move(route));
}

}  // namespace ispq::server::http
