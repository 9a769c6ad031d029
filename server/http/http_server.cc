#include "server/http/http_server.h"

#include <cstdint>
#include <string>
#include <utility>

#include "absl/status/status.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/time/clock.h"
#include "absl/time/time.h"
#include "server/http/event_stream_route.h"
#include "server/http/http_exchange.h"
#include "server/http/job_routes.h"
#include "server/http/operator_routes.h"
#include "server/http/web_routes.h"
#include "spdlog/spdlog.h"

namespace ispq::server::http {
namespace {

// Threads beyond the event streams' own: for the JSON API, the probes, /metrics and the page.
constexpr int kRequestThreads = 8;
constexpr time_t kReadTimeoutSeconds = 30;   // a client sending a body slowly
constexpr time_t kWriteTimeoutSeconds = 30;  // a client not reading its answer or events
constexpr time_t kKeepAliveSeconds = 5;      // an idle connection holds a thread this long
// At shutdown, how long event streams may take to write their jobs' last events.
constexpr absl::Duration kStreamFlushTime = absl::Seconds(3);

absl::StatusOr<std::pair<std::string, int>> HostAndPort(const std::string& address) {
  const size_t colon = address.rfind(':');
  int port = -1;
  if (colon == std::string::npos || colon == 0 ||
      !absl::SimpleAtoi(address.substr(colon + 1), &port) || port < 0 || port > 65535) {
    return absl::InvalidArgumentError(
        absl::StrCat("--http_listen ", address, " is not HOST:PORT (e.g. 127.0.0.1:8080)"));
  }
  std::string host = address.substr(0, colon);
  if (host.size() > 2 && host.front() == '[' && host.back() == ']') {
    host = host.substr(1, host.size() - 2);  // [::1]:8080
  }
  return std::make_pair(host, port);
}

}  // namespace

HttpServer::HttpServer(HttpParts parts, HttpLimits limits)
    : parts_(std::move(parts)), limits_(limits), streams_(limits.max_event_streams) {}

absl::StatusOr<std::unique_ptr<HttpServer>> HttpServer::Start(const std::string& listen_address,
                                                              HttpParts parts, HttpLimits limits) {
  absl::StatusOr<std::pair<std::string, int>> address = HostAndPort(listen_address);
  if (!address.ok()) return address.status();
  std::unique_ptr<HttpServer> http(new HttpServer(std::move(parts), limits));
  httplib::Server& server = http->server_;
  const int threads = limits.max_event_streams + kRequestThreads;
  server.new_task_queue = [threads] { return new httplib::ThreadPool(threads); };
  server.set_payload_max_length(static_cast<size_t>(limits.max_body_bytes));
  server.set_read_timeout(kReadTimeoutSeconds, 0);
  server.set_write_timeout(kWriteTimeoutSeconds, 0);
  server.set_keep_alive_timeout(kKeepAliveSeconds);
  server.set_tcp_nodelay(true);  // events go out as they come, not batched by Nagle
  server.set_exception_handler(
      [](const httplib::Request& request, httplib::Response& response, std::exception_ptr) {
        spdlog::error("event=http_exception method={} path={}", request.method, request.path);
        ReplyError(response, absl::InternalError("the request failed inside the server"));
      });
  // Errors cpp-httplib answers itself (no route: 404, a body past the limit: 413, a malformed
  // request: 400) get the same JSON body as the API's; the API's own errors keep theirs.
  server.set_error_handler([](const httplib::Request& request, httplib::Response& response) {
    if (!response.body.empty()) return;
    if (response.status == 404) {
      ReplyError(response, absl::NotFoundError(
                               absl::StrCat("no route for ", request.method, " ", request.path)));
    } else if (response.status == 413) {
      // cpp-httplib also refuses form-encoded bodies (curl -d's default type) past 8 KiB.
      ReplyError(response, absl::ResourceExhaustedError(
                               "the body is larger than the server accepts (--max_message_bytes), "
                               "or is form-encoded and larger than 8 KiB: send JSON with "
                               "Content-Type: application/json"));
      response.status = 413;
    } else {
      ReplyError(response, absl::InvalidArgumentError(absl::StrCat("the HTTP request was refused (",
                                                                   response.status, ")")));
    }
  });

  AddJobRoutes(server, http->parts_, http->limits_);
  AddEventStreamRoute(server, http->parts_, http->streams_);
  AddOperatorRoutes(server, http->parts_, http->streams_);
  AddWebRoutes(server);

  const auto& [host, port] = *address;
  if (port == 0) {
    http->port_ = server.bind_to_any_port(host);
  } else if (server.bind_to_port(host, port)) {
    http->port_ = port;
  }
  if (http->port_ <= 0) {
    http->stopped_ = true;
    return absl::UnavailableError(absl::StrCat("cannot listen on ", listen_address, " (HTTP)"));
  }
  HttpServer* const self = http.get();
  http->listener_ = std::thread([self] { self->server_.listen_after_bind(); });
  // Stop only works on a running server: wait until the listener has taken over the socket.
  const absl::Time deadline = absl::Now() + absl::Seconds(10);
  while (!server.is_running() && absl::Now() < deadline) absl::SleepFor(absl::Milliseconds(1));
  return http;
}

HttpServer::~HttpServer() { Stop(); }

void HttpServer::Stop() {
  if (stopped_) return;
  stopped_ = true;
  // The streams first write what their jobs still have (the jobs have ended by now), then end;
  // stopping the listener before would cut them between two events.
  streams_.StopAll();
  const absl::Time deadline = absl::Now() + kStreamFlushTime;
  while (streams_.open_streams() > 0 && absl::Now() < deadline) {
    absl::SleepFor(absl::Milliseconds(10));
  }
  server_.stop();
  if (listener_.joinable()) listener_.join();
}

}  // namespace ispq::server::http
