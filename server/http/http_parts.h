// What the HTTP side works with: the same service, authenticator, memory budget and metrics as
// the gRPC side (everything owned by QuantizerServer, which outlives the HTTP server), and the
// server's liveness and readiness as the gRPC health service reports them.
#ifndef ISPQ_SERVER_HTTP_HTTP_PARTS_H_
#define ISPQ_SERVER_HTTP_HTTP_PARTS_H_

#include <cstdint>
#include <functional>

#include "server/authenticator.h"
#include "server/memory_admission.h"
#include "server/quantizer_service.h"
#include "server/server_metrics.h"

namespace ispq::server::http {

struct HttpParts {
  QuantizerService& service;
  const Authenticator& authenticator;
  MemoryAdmission& memory;
  ServerMetrics& metrics;
  std::function<bool()> live;   // SERVING until shutdown begins
  std::function<bool()> ready;  // would accept a new job now
};

struct HttpLimits {
  int64_t max_body_bytes = 32 << 20;  // --max_message_bytes, as gRPC's
  int max_event_streams = 32;         // concurrent server-sent-event streams
};

}  // namespace ispq::server::http

#endif  // ISPQ_SERVER_HTTP_HTTP_PARTS_H_
