// SPDX-License-Identifier: Apache-2.0
// What operators and orchestrators poll, unauthenticated and plaintext even when gRPC uses TLS
// (as gRPC's health service stays open): GET /healthz (liveness: 200 until shutdown begins, then
// 503), GET /readyz (readiness: 200 while the server would accept a new job, 503 while it would
// refuse one or is shutting down; the same test as the gRPC "readiness" health service) and GET
// /metrics (server/http/prometheus_text.h). They hold no client data: counts only, so any Host
// may ask for them (orchestrators probe by IP address). The probes answer on the event thread
// from two cheap functions that never wait; /metrics, which counts the jobs in the store, on a
// thread of its own, so that neither waits behind the other routes.
#ifndef ISPQ_SERVER_HTTP_OPERATOR_ROUTES_H_
#define ISPQ_SERVER_HTTP_OPERATOR_ROUTES_H_

#include "server/http/connection_deadlines.h"
#include "server/http/event_streams.h"
#include "server/http/http_parts.h"
#include "server/http/http_refusals.h"
#include "server/http/http_router.h"

namespace ispq::server::http {

// What the HTTP side counts of itself, for /metrics.
struct HttpSideCounts {
  const EventStreams& streams;
  const ConnectionDeadlines& connections;
  const HttpRefusals& refusals;
};

// `parts` and what `counts` refers to must outlive `router`.
void AddOperatorRoutes(Router& router, const HttpParts& parts, HttpSideCounts counts);

}  // namespace ispq::server::http

#endif  // ISPQ_SERVER_HTTP_OPERATOR_ROUTES_H_
