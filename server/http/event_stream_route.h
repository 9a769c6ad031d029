// SPDX-License-Identifier: Apache-2.0
// GET /v1/jobs/{id}:watch: a job's events as server-sent events (text/event-stream), the same
// events as gRPC's WatchJob, from the same log (server/http/job_event_feed.h):
//
//   id: <event sequence number>
//   data: <the ispq.v1.QuantizeEvent in protobuf JSON, one line>
//
// and, after the terminal event (result or error), one `event: end` whose data is the stream's
// final status as {"code", "status", "message"} (OK after a result), after which the server
// closes the stream; a browser's EventSource should close on it rather than reconnect. Where to
// start is `?fromEvent=N` (WatchJob's from_event), or the `Last-Event-ID` header that a
// reconnecting EventSource sends, which resumes after that event (from_event = id + 1) and takes
// precedence. A comment line is sent every 15 s of silence, so that a vanished client is noticed
// by a failed write. Streams are bounded in number (server/http/event_streams.h) and hold no
// thread: a stream with nothing to send is parked until its job has a new event
// (server/http/job_event_feed.h).
#ifndef ISPQ_SERVER_HTTP_EVENT_STREAM_ROUTE_H_
#define ISPQ_SERVER_HTTP_EVENT_STREAM_ROUTE_H_

#include "server/http/event_streams.h"
#include "server/http/http_parts.h"
#include "server/http/http_router.h"

namespace ispq::server::http {

// `parts` and `streams` must outlive `router` and the streams it opens.
void AddEventStreamRoute(Router& router, const HttpParts& parts, EventStreams& streams);

}  // namespace ispq::server::http

#endif  // ISPQ_SERVER_HTTP_EVENT_STREAM_ROUTE_H_
