// SPDX-License-Identifier: Apache-2.0
// The HTTP side of ispq-server (--http_listen): it serves the JSON API over jobs
// (server/http/job_routes.h), job events as server-sent events (server/http/event_stream_route.h),
// the operator endpoints /healthz, /readyz and /metrics (server/http/operator_routes.h) and the
// live web view (server/http/web_routes.h). It shares the gRPC side's service, authentication,
// limits and memory budget (server/http/http_parts.h).
//
// HTTPS when given a certificate and key (server/http/http_tls.h; by default gRPC's, so that a
// TLS deployment exposes the web view and /metrics over TLS too), else plaintext, for a trusted
// network or behind a TLS-terminating proxy. TLS runs in libmicrohttpd (GnuTLS, TLS 1.2 and 1.3
// only) on the same event threads; it asks for no client certificate, so where gRPC names
// principals by client certificate and no tokens are configured, the job routes answer 401
// (server/auth/authenticator.h).
//
// Bounded before it trusts anything. It runs on GNU libmicrohttpd rather than cpp-httplib, whose
// Debian build (0.11) inflates gzip and deflate bodies whole before any handler or authentication
// runs, does not enforce its header and line limits (a 256 MiB header line was read whole), reads
// chunked and length-less bodies whole whatever the payload limit, and serves each connection on
// a thread of a fixed pool, so that a few hundred slow or idle connections starve the probes.
// libmicrohttpd is event-driven (epoll: a slow or idle connection costs a socket and a small
// memory pool, not a thread), bounds each connection's request line and headers by that pool
// (beyond it, it answers 414 or 431 itself, with its own short body), limits connections and
// idle time, hands a body over as it arrives, never decodes a Content-Encoding, and lets a
// request be answered later from another thread (suspend and resume). On that:
//
//   * Connections: at most HttpLimits::max_connections, closed after idle_timeout without traffic
//     or when a request's head or body is not complete within its deadline
//     (server/http/connection_deadlines.h), so no number of slow or idle clients holds the
//     server for long, and none holds a thread.
//   * Requests are checked from their head before any body is read (server/http/
//     request_dispatcher.h), bodies are taken as they arrive within --max_message_bytes and the
//     memory budget (server/http/request_body.h), and JSON bodies are checked before protobuf
//     parses them (server/http/json_guard.h). Host and Origin guard against DNS rebinding and
//     cross-site requests (server/http/origin_policy.h). Refusals have the API's JSON error body.
//   * Threads: two event threads (libmicrohttpd's) read and write every connection and run only
//     what never waits: the probes (/healthz, /readyz), the web view's files, the checks and the
//     body bytes. /metrics, the job lookups and the submissions run on small pools of their own
//     (server/http/handler_pool.h) while their connection is suspended; event streams hold no
//     thread at all (server/http/job_event_feed.h).
#ifndef ISPQ_SERVER_HTTP_HTTP_SERVER_H_
#define ISPQ_SERVER_HTTP_HTTP_SERVER_H_

#include <memory>
#include <optional>
#include <string>
#include <thread>

#include "absl/base/thread_annotations.h"
#include "absl/status/statusor.h"
#include "absl/synchronization/mutex.h"
#include "server/http/connection_deadlines.h"
#include "server/http/event_streams.h"
#include "server/http/geometry_cache.h"
#include "server/http/handler_pool.h"
#include "server/http/http_parts.h"
#include "server/http/http_refusals.h"
#include "server/http/http_router.h"
#include "server/http/http_tls.h"
#include "server/http/origin_policy.h"
#include "server/http/pending_exchanges.h"
#include "server/http/request_dispatcher.h"
#include "server/http/suspensions.h"

struct MHD_Daemon;

namespace ispq::server::http {

class HttpServer {
 public:
  // Binds `listen_address` (HOST:PORT, port 0 picks one) and serves on threads of its own, over
  // TLS with `tls` if given. UNAVAILABLE if the address cannot be bound, INVALID_ARGUMENT if it is
  // malformed, FAILED_PRECONDITION if TLS is asked for and libmicrohttpd was built without it.
  static absl::StatusOr<std::unique_ptr<HttpServer>> Start(
      const std::string& listen_address, HttpParts parts, HttpLimits limits,
      std::optional<HttpTlsMaterial> tls = std::nullopt);
  ~HttpServer();
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;

  int port() const { return port_; }
  bool tls() const { return tls_.has_value(); }

  // Lets the event streams write their jobs' last events (for up to a few seconds), answers the
  // requests still waiting with 503, stops listening and joins the threads. Idempotent.
  void Stop();

 private:
  HttpServer(HttpParts parts, HttpLimits limits);

  absl::Status Serve(int listen_socket, bool ipv6);
  // Every 250 ms: answers requests past their deadline, shuts down slow connections, wakes the
  // event streams for their keepalives.
  void Maintain();

  const HttpParts parts_;
  const HttpLimits limits_;
  // Kept for the daemon's lifetime: libmicrohttpd is handed pointers to the PEM text.
  std::optional<HttpTlsMaterial> tls_;
  Suspensions suspensions_;
  EventStreams streams_;
  PendingExchanges pending_;
  ConnectionDeadlines deadlines_;
  HttpRefusals refusals_;
  GeometryCache geometry_;  // used by the routes' handlers: outlives the pools
  Router router_;
  std::unique_ptr<OriginPolicy> origins_;
  HandlerPool operator_pool_;
  HandlerPool lookup_pool_;
  HandlerPool parse_pool_;
  std::unique_ptr<RequestDispatcher> dispatcher_;
  MHD_Daemon* daemon_ = nullptr;
  int listen_socket_ = -1;
  int port_ = 0;
  bool stopped_ = false;

  absl::Mutex maintenance_mutex_;
  bool stopping_ ABSL_GUARDED_BY(maintenance_mutex_) = false;
  std::thread maintenance_;
};

}  // namespace ispq::server::http

#endif  // ISPQ_SERVER_HTTP_HTTP_SERVER_H_
