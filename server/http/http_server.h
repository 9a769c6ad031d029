// The HTTP side of ispq-server (--http_listen): a cpp-httplib server on its own threads that
// serves the JSON API over jobs (server/http/job_routes.h), job events as server-sent events
// (server/http/event_stream_route.h), the operator endpoints /healthz, /readyz and /metrics
// (server/http/operator_routes.h) and the live web view (server/http/web_routes.h). It shares
// the gRPC side's service, authentication, limits and memory budget (server/http/http_parts.h).
//
// Plaintext only: it is meant for probes, metrics scrapers and a web view on a trusted network
// or behind a TLS-terminating proxy. Where gRPC names principals by client certificate and no
// tokens are configured, the job routes answer 401 (server/authenticator.h).
//
// Threads and bounds: cpp-httplib serves each connection on one thread of a fixed pool of
// max_event_streams + kRequestThreads threads, so the open event streams (at most
// max_event_streams) never take the threads the JSON API and the probes need. Request bodies are
// at most max_body_bytes (413 beyond, before they are read); reads and writes time out; idle
// keep-alive connections are closed after a few seconds.
#ifndef ISPQ_SERVER_HTTP_HTTP_SERVER_H_
#define ISPQ_SERVER_HTTP_HTTP_SERVER_H_

#include <memory>
#include <string>
#include <thread>

#include "absl/status/statusor.h"
#include "httplib.h"
#include "server/http/event_streams.h"
#include "server/http/http_parts.h"

namespace ispq::server::http {

class HttpServer {
 public:
  // Binds `listen_address` (HOST:PORT, port 0 picks one) and serves on a thread of its own.
  // UNAVAILABLE if the address cannot be bound, INVALID_ARGUMENT if it is malformed.
  static absl::StatusOr<std::unique_ptr<HttpServer>> Start(const std::string& listen_address,
                                                           HttpParts parts, HttpLimits limits);
  ~HttpServer();
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;

  int port() const { return port_; }

  // Ends the event streams (each within about a second), stops listening and joins the
  // threads. Idempotent.
  void Stop();

 private:
  HttpServer(HttpParts parts, HttpLimits limits);

  const HttpParts parts_;
  const HttpLimits limits_;
  EventStreams streams_;
  httplib::Server server_;
  std::thread listener_;
  int port_ = 0;
  bool stopped_ = false;
};

}  // namespace ispq::server::http

#endif  // ISPQ_SERVER_HTTP_HTTP_SERVER_H_
