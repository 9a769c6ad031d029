// SPDX-License-Identifier: Apache-2.0
// What the HTTP side works with: the same service, authenticator, memory budget and metrics as
// the gRPC side (everything owned by QuantizerServer, which outlives the HTTP server), and the
// server's liveness and readiness as the gRPC health service reports them; and its bounds, which
// hold before anything of a request is trusted (server/http/http_server.h).
#ifndef ISPQ_SERVER_HTTP_HTTP_PARTS_H_
#define ISPQ_SERVER_HTTP_HTTP_PARTS_H_

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "absl/time/time.h"
#include "server/admission/memory_admission.h"
#include "server/auth/authenticator.h"
#include "server/metrics/server_metrics.h"
#include "server/service/job_service.h"

namespace ispq::server::http {

struct HttpParts {
  JobService& service;
  const Authenticator& authenticator;
  MemoryAdmission& memory;
  ServerMetrics& metrics;
  // Both are asked on the event thread for every probe: they must be cheap and never wait.
  std::function<bool()> live;   // SERVING until shutdown begins
  std::function<bool()> ready;  // would accept a new job now
};

struct HttpLimits {
  int64_t max_body_bytes = 32 << 20;  // --max_message_bytes, as gRPC's
  int max_event_streams = 32;         // concurrent server-sent-event streams
  // --http_allowed_hosts: the Host header values served ("name" any port, "name:port" that
  // port, "*" any); empty: the listen address's host, localhost, 127.0.0.1 and [::1] at the
  // bound port.
  std::vector<std::string> allowed_hosts;

  // Not flags: bounds no browser or client of ours comes near.
  int64_t max_target_bytes = 8 << 10;   // the request target (path and query): 414 beyond
  int64_t max_header_bytes = 32 << 10;  // all header lines together: 431 beyond
  int max_headers = 100;                // header lines: 431 beyond
  int max_connections = 1024;           // open at once; more are closed as they come
  absl::Duration idle_timeout = absl::Seconds(10);  // a connection with no traffic is closed
  // A request must have sent its head within this of its connection (or its previous request)
  // and its body within body_deadline of its head, however slowly the bytes trickle in.
  absl::Duration head_deadline = absl::Seconds(10);
  absl::Duration body_deadline = absl::Seconds(120);
  absl::Duration answer_timeout = absl::Seconds(60);  // then 504 (a submission: retry it)
};

}  // namespace ispq::server::http

#endif  // ISPQ_SERVER_HTTP_HTTP_PARTS_H_
