// What operators and orchestrators poll, unauthenticated and plaintext even when gRPC uses TLS
// (as gRPC's health service stays open): GET /healthz (liveness: 200 until shutdown begins, then
// 503), GET /readyz (readiness: 200 while the server would accept a new job, 503 while it would
// refuse one or is shutting down; the same test as the gRPC "readiness" health service) and GET
// /metrics (server/http/prometheus_text.h). They hold no client data: counts only.
#ifndef ISPQ_SERVER_HTTP_OPERATOR_ROUTES_H_
#define ISPQ_SERVER_HTTP_OPERATOR_ROUTES_H_

#include "httplib.h"
#include "server/http/event_streams.h"
#include "server/http/http_parts.h"

namespace ispq::server::http {

// `parts` and `streams` must outlive `server`.
void AddOperatorRoutes(httplib::Server& server, const HttpParts& parts,
                       const EventStreams& streams);

}  // namespace ispq::server::http

#endif  // ISPQ_SERVER_HTTP_OPERATOR_ROUTES_H_
