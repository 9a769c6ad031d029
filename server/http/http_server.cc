// SPDX-License-Identifier: Apache-2.0
#include "server/http/http_server.h"

#include <microhttpd.h>
#include <netdb.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdarg>
#include <cstdio>
#include <string>
#include <utility>

#include "absl/status/status.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/time/clock.h"
#include "absl/time/time.h"
#include "server/http/event_stream_route.h"
#include "server/http/geometry_route.h"
#include "server/http/job_routes.h"
#include "server/http/mhd_callbacks.h"
#include "server/http/operator_routes.h"
#include "server/http/web_routes.h"
#include "spdlog/spdlog.h"

namespace ispq::server::http {
namespace {

// libmicrohttpd's threads: they only read, write and run what never waits, so two suffice.
constexpr unsigned kEventThreads = 2;
// Threads of the pools: /metrics; lookups, cancels and watches; submissions (each converting a
// body of up to --max_message_bytes, which is also memory outside the budget's estimate).
constexpr int kOperatorThreads = 1;
constexpr int kLookupThreads = 4;
constexpr int kParseThreads = 2;
// A connection's memory pool: the request line and headers (HttpLimits' 8 + 32 KiB), the
// parsed header entries and the read buffer fit; libmicrohttpd answers 414 or 431 beyond.
constexpr size_t kConnectionMemoryBytes = 64 << 10;
// At shutdown, how long event streams may take to write their jobs' last events, and how long
// answered requests may take to leave their suspension.
constexpr absl::Duration kStreamFlushTime = absl::Seconds(3);
constexpr absl::Duration kResumeTime = absl::Seconds(2);
constexpr absl::Duration kMaintenancePeriod = absl::Milliseconds(250);
constexpr int kStreamWakeEvery = 4;  // periods: the streams look at their keepalive each second
// GnuTLS priorities for HTTPS: its defaults without TLS 1.0 and 1.1, which no current browser or
// Prometheus speaks and which have known weaknesses.
constexpr char kTlsPriorities[] = "NORMAL:-VERS-ALL:+VERS-TLS1.3:+VERS-TLS1.2";

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

// A listening socket bound to `host`:`port`, or -1; `ipv6` says which family.
int Listen(const std::string& host, int port, bool* ipv6) {
  addrinfo hints = {};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_PASSIVE | AI_NUMERICSERV;
  addrinfo* found = nullptr;
  if (getaddrinfo(host.c_str(), std::to_string(port).c_str(), &hints, &found) != 0) return -1;
  int listening = -1;
  for (addrinfo* at = found; at != nullptr && listening < 0; at = at->ai_next) {
    const int fd = socket(at->ai_family, at->ai_socktype | SOCK_CLOEXEC, at->ai_protocol);
    if (fd < 0) continue;
    const int on = 1;
    setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &on, sizeof(on));
    if (bind(fd, at->ai_addr, at->ai_addrlen) == 0 && listen(fd, SOMAXCONN) == 0) {
      listening = fd;
      *ipv6 = at->ai_family == AF_INET6;
    } else {
      close(fd);
    }
  }
  freeaddrinfo(found);
  return listening;
}

int BoundPort(int fd) {
  sockaddr_storage address = {};
  socklen_t length = sizeof(address);
  if (getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length) != 0) return 0;
  if (address.ss_family == AF_INET6) {
    return ntohs(reinterpret_cast<const sockaddr_in6*>(&address)->sin6_port);
  }
  return ntohs(reinterpret_cast<const sockaddr_in*>(&address)->sin_port);
}

// libmicrohttpd's messages (refused requests, closed connections) are routine under attack:
// debug level only.
void OnLibraryMessage(void* /*unused*/, const char* format, va_list arguments) {
  if (!spdlog::should_log(spdlog::level::debug)) return;
  char text[512];
  std::vsnprintf(text, sizeof(text), format, arguments);
  spdlog::debug("event=http_library message=\"{}\"", text);
}

}  // namespace

HttpServer::HttpServer(HttpParts parts, HttpLimits limits)
    : parts_(std::move(parts)),
      limits_(std::move(limits)),
      streams_(limits_.max_event_streams),
      deadlines_(limits_.head_deadline, limits_.body_deadline),
      geometry_(parts_.memory),
      operator_pool_(kOperatorThreads, "ispq-http-ops"),
      lookup_pool_(kLookupThreads, "ispq-http-look"),
      parse_pool_(kParseThreads, "ispq-http-parse") {}

absl::StatusOr<std::unique_ptr<HttpServer>> HttpServer::Start(const std::string& listen_address,
                                                              HttpParts parts, HttpLimits limits,
                                                              std::optional<HttpTlsMaterial> tls) {
  absl::StatusOr<std::pair<std::string, int>> address = HostAndPort(listen_address);
  if (!address.ok()) return address.status();
  if (tls.has_value() && !HttpTlsSupported()) {
    return absl::FailedPreconditionError(
        "this libmicrohttpd was built without TLS, so the HTTP side cannot serve HTTPS: serve it "
        "behind a TLS-terminating proxy with --http_plaintext, or use a libmicrohttpd with GnuTLS");
  }
  const auto& [host, port] = *address;
  bool ipv6 = false;
  const int listening = Listen(host, port, &ipv6);
  if (listening < 0) {
    return absl::UnavailableError(absl::StrCat("cannot listen on ", listen_address, " (HTTP)"));
  }
  std::unique_ptr<HttpServer> http(new HttpServer(std::move(parts), std::move(limits)));
  http->tls_ = std::move(tls);
  http->listen_socket_ = listening;
  http->port_ = BoundPort(listening);
  http->origins_ = std::make_unique<OriginPolicy>(http->limits_.allowed_hosts, host, http->port_);
  if (absl::Status served = http->Serve(listening, ipv6); !served.ok()) {
    http->stopped_ = true;
    close(listening);
    return served;
  }
  return http;
}

absl::Status HttpServer::Serve(int listen_socket, bool ipv6) {
  AddJobRoutes(router_, parts_, limits_, &geometry_);
  AddGeometryRoute(router_, parts_, geometry_);
  AddEventStreamRoute(router_, parts_, streams_);
  AddOperatorRoutes(
      router_, parts_,
      HttpSideCounts{.streams = streams_, .connections = deadlines_, .refusals = refusals_});
  AddWebRoutes(router_);
  dispatcher_ = std::make_unique<RequestDispatcher>(DispatcherParts{
      .parts = parts_,
      .limits = limits_,
      .router = router_,
      .origins = *origins_,
      .lanes = {.operator_lane = &operator_pool_, .lookup = &lookup_pool_, .parse = &parse_pool_},
      .pending = pending_,
      .deadlines = deadlines_,
      .suspensions = suspensions_,
      .refusals = refusals_});
  unsigned int flags =
      MHD_USE_EPOLL_INTERNAL_THREAD | MHD_ALLOW_SUSPEND_RESUME | (ipv6 ? MHD_USE_IPv6 : 0);
  // Without TLS the options end before the certificate's: libmicrohttpd reads up to MHD_OPTION_END.
  MHD_OptionItem tls_options[] = {
      {MHD_OPTION_HTTPS_MEM_CERT, 0, nullptr},
      {MHD_OPTION_HTTPS_MEM_KEY, 0, nullptr},
      {MHD_OPTION_HTTPS_PRIORITIES, 0, const_cast<char*>(kTlsPriorities)},
      {MHD_OPTION_END, 0, nullptr}};
  if (tls_.has_value()) {
    flags |= MHD_USE_TLS;
    tls_options[0].ptr_value = tls_->cert_pem.data();
    tls_options[1].ptr_value = tls_->key_pem.data();
  } else {
    tls_options[0] = {MHD_OPTION_END, 0, nullptr};
  }
  daemon_ = MHD_start_daemon(
      flags, 0, nullptr, nullptr, &OnMhdRequest, dispatcher_.get(), MHD_OPTION_LISTEN_SOCKET,
      listen_socket, MHD_OPTION_THREAD_POOL_SIZE, kEventThreads, MHD_OPTION_CONNECTION_MEMORY_LIMIT,
      kConnectionMemoryBytes, MHD_OPTION_CONNECTION_LIMIT,
      static_cast<unsigned>(limits_.max_connections), MHD_OPTION_CONNECTION_TIMEOUT,
      static_cast<unsigned>(absl::ToInt64Seconds(limits_.idle_timeout)),
      MHD_OPTION_NOTIFY_COMPLETED, &OnMhdRequestCompleted, dispatcher_.get(),
      MHD_OPTION_NOTIFY_CONNECTION, &OnMhdConnection, &deadlines_, MHD_OPTION_EXTERNAL_LOGGER,
      &OnLibraryMessage, nullptr, MHD_OPTION_ARRAY, tls_options, MHD_OPTION_END);
  if (daemon_ == nullptr) {
    return absl::UnavailableError(tls_.has_value()
                                      ? "cannot start the HTTPS server (libmicrohttpd with TLS)"
                                      : "cannot start the HTTP server (libmicrohttpd)");
  }
  maintenance_ = std::thread([this] { Maintain(); });
  return absl::OkStatus();
}

void HttpServer::Maintain() {
  for (int tick = 1;; ++tick) {
    {
      absl::MutexLock lock(&maintenance_mutex_);
      auto stopping = [this]()
                          ABSL_EXCLUSIVE_LOCKS_REQUIRED(maintenance_mutex_) { return stopping_; };
      if (maintenance_mutex_.AwaitWithTimeout(absl::Condition(&stopping), kMaintenancePeriod)) {
        return;
      }
    }
    const absl::Time now = absl::Now();
    pending_.Expire(now);
    deadlines_.ShutDownLate(now);
    if (tick % kStreamWakeEvery == 0) streams_.WakeAll();
  }
}

HttpServer::~HttpServer() { Stop(); }

void HttpServer::Stop() {
  if (stopped_) return;
  stopped_ = true;
  dispatcher_->StopAccepting();
  // No new connections. The socket is ours to close, unless libmicrohttpd could not give it back.
  if (MHD_quiesce_daemon(daemon_) == MHD_INVALID_SOCKET) listen_socket_ = -1;
  // The streams first write what their jobs still have (the jobs have ended by now), then end;
  // stopping the daemon before would cut them between two events.
  streams_.StopAll();
  const absl::Time flushed = absl::Now() + kStreamFlushTime;
  while (streams_.open_streams() > 0 && absl::Now() < flushed) {
    absl::SleepFor(absl::Milliseconds(10));
  }
  pending_.StopAll();
  const absl::Time resumed = absl::Now() + kResumeTime;
  while (suspensions_.suspended() > 0 && absl::Now() < resumed) {
    absl::SleepFor(absl::Milliseconds(10));
  }
  if (suspensions_.suspended() == 0) {
    MHD_stop_daemon(daemon_);
  } else {
    // libmicrohttpd aborts when stopped with a suspended connection; the process is ending.
    spdlog::error("event=http_stop_incomplete suspended_connections={}", suspensions_.suspended());
  }
  if (listen_socket_ >= 0) close(listen_socket_);
  {
    absl::MutexLock lock(&maintenance_mutex_);
    stopping_ = true;
  }
  if (maintenance_.joinable()) maintenance_.join();
  operator_pool_.Stop();
  lookup_pool_.Stop();
  parse_pool_.Stop();
}

}  // namespace ispq::server::http
