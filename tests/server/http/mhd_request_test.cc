// SPDX-License-Identifier: Apache-2.0
// A request's head as libmicrohttpd parsed it, copied for the checks and the routes: method, path
// without the query, header names in lower case (values as sent) in the order received, the query
// decoded, the peer's address and port, and the head's size as the framing limits count it. A
// bare libmicrohttpd daemon on loopback reads real requests; its callback copies each head.
#include "server/http/mhd_request.h"

#include <arpa/inet.h>
#include <microhttpd.h>
#include <netinet/in.h>
#include <sys/socket.h>

#include <string>
#include <utility>

#include "absl/base/thread_annotations.h"
#include "absl/strings/str_cat.h"
#include "absl/synchronization/mutex.h"
#include "gtest/gtest.h"
#include "tests/server/http/http_test_service.h"

namespace ispq::server::http {
namespace {

// What the request callback saw of the last request.
struct SeenHead {
  HttpRequest request;
  HeadSize size;
  int socket_peer_port = -1;   // of SocketOf's socket, by getpeername
  int socket_local_port = -1;  // by getsockname
};

int PortOf(const sockaddr_storage& address) {
  if (address.ss_family == AF_INET6) {
    return ntohs(reinterpret_cast<const sockaddr_in6*>(&address)->sin6_port);
  }
  return ntohs(reinterpret_cast<const sockaddr_in*>(&address)->sin_port);
}

class MhdRequestTest : public ::testing::Test {
 protected:
  // A daemon on 127.0.0.1 (or [::1]) port 0 whose callback records each head; false if it does
  // not start.
  bool StartDaemon(bool ipv6) {
    sockaddr_storage address = {};
    if (ipv6) {
      auto* v6 = reinterpret_cast<sockaddr_in6*>(&address);
      v6->sin6_family = AF_INET6;
      v6->sin6_addr = in6addr_loopback;
    } else {
      auto* v4 = reinterpret_cast<sockaddr_in*>(&address);
      v4->sin_family = AF_INET;
      v4->sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    }
    daemon_ = MHD_start_daemon(MHD_USE_INTERNAL_POLLING_THREAD | (ipv6 ? MHD_USE_IPv6 : 0), 0,
                               nullptr, nullptr, &OnRequest, this, MHD_OPTION_SOCK_ADDR,
                               reinterpret_cast<sockaddr*>(&address), MHD_OPTION_END);
    if (daemon_ == nullptr) return false;
    port_ = MHD_get_daemon_info(daemon_, MHD_DAEMON_INFO_BIND_PORT)->port;
    return port_ > 0;
  }

  ~MhdRequestTest() override {
    if (daemon_ != nullptr) MHD_stop_daemon(daemon_);
  }

  // The last head seen (then no more).
  SeenHead TakeSeen() {
    absl::MutexLock lock(&mutex_);
    return std::move(seen_);
  }

  static MHD_Result OnRequest(void* self, MHD_Connection* connection, const char* url,
                              const char* method, const char* /*version*/,
                              const char* /*upload_data*/, size_t* upload_data_size,
                              void** context) {
    if (*context == nullptr) {  // the head is in
      *context = self;
      static_cast<MhdRequestTest*>(self)->Record(connection, url, method);
      return MHD_YES;
    }
    if (*upload_data_size != 0) {
      *upload_data_size = 0;
      return MHD_YES;
    }
    MHD_Response* response = MHD_create_response_from_buffer(0, nullptr, MHD_RESPMEM_PERSISTENT);
    const MHD_Result queued = MHD_queue_response(connection, 204, response);
    MHD_destroy_response(response);
    return queued;
  }

  void Record(MHD_Connection* connection, const char* url, const char* method) {
    SeenHead seen;
    seen.size = ReadHead(connection, url, method, seen.request);
    const int fd = SocketOf(connection);
    sockaddr_storage peer = {};
    socklen_t length = sizeof(peer);
    if (fd >= 0 && getpeername(fd, reinterpret_cast<sockaddr*>(&peer), &length) == 0) {
      seen.socket_peer_port = PortOf(peer);
    }
    sockaddr_storage local = {};
    length = sizeof(local);
    if (fd >= 0 && getsockname(fd, reinterpret_cast<sockaddr*>(&local), &length) == 0) {
      seen.socket_local_port = PortOf(local);
    }
    absl::MutexLock lock(&mutex_);
    seen_ = std::move(seen);
  }

  MHD_Daemon* daemon_ = nullptr;
  int port_ = 0;
  absl::Mutex mutex_;
  SeenHead seen_ ABSL_GUARDED_BY(mutex_);
};

TEST_F(MhdRequestTest, CopiesTheHeadWithLowerCaseNamesAndTheDecodedQuery) {
  ASSERT_TRUE(StartDaemon(/*ipv6=*/false));
  int client_port = 0;
  const std::string answer =
      RawHttpExchange(port_,
                      "POST /v1/jobs/abc:cancel?b=x%20y&a=1&a=2&flag HTTP/1.1\r\n"
                      "Host: 127.0.0.1\r\nX-Custom-Name: Mixed Value\r\nAUTHORIZATION: Bearer T\r\n"
                      "Content-Length: 0\r\nConnection: close\r\n\r\n",
                      /*ipv6=*/false, &client_port);
  ASSERT_EQ(RawStatus(answer), 204) << answer;
  const SeenHead seen = TakeSeen();
  const HttpRequest& request = seen.request;
  EXPECT_EQ(request.method, "POST");
  EXPECT_EQ(request.path, "/v1/jobs/abc:cancel");
  EXPECT_EQ(request.headers, (HttpFields{{"host", "127.0.0.1"},
                                         {"x-custom-name", "Mixed Value"},
                                         {"authorization", "Bearer T"},
                                         {"content-length", "0"},
                                         {"connection", "close"}}));
  EXPECT_EQ(request.Header("authorization"), "Bearer T");
  // Parameter names keep their case; values are decoded; a bare name has an empty value.
  EXPECT_EQ(request.query, (HttpFields{{"b", "x y"}, {"a", "1"}, {"a", "2"}, {"flag", ""}}));
  EXPECT_EQ(request.peer, absl::StrCat("127.0.0.1:", client_port));
  EXPECT_TRUE(request.body.empty());
  EXPECT_TRUE(request.id.empty());

  // The target: the path and each parameter with its "=" and "&" (and slack), as the limit of
  // server/http/request_framing.h counts it; the headers each with ": " and CRLF.
  EXPECT_EQ(seen.size.target_bytes, std::string("/v1/jobs/abc:cancel").size() + (1 + 3 + 4) +
                                        (1 + 1 + 4) + (1 + 1 + 4) + (4 + 0 + 4));
  size_t header_bytes = 0;
  for (const auto& [name, value] : request.headers) header_bytes += name.size() + value.size() + 4;
  EXPECT_EQ(seen.size.header_bytes, header_bytes);
  EXPECT_EQ(seen.size.header_count, 5u);
}

// The socket is the connection's own: the deadlines shut it down when the client is late.
TEST_F(MhdRequestTest, SocketOfIsTheConnectionsSocket) {
  ASSERT_TRUE(StartDaemon(/*ipv6=*/false));
  int client_port = 0;
  const std::string answer = RawHttpExchange(
      port_, "GET / HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n", false, &client_port);
  ASSERT_EQ(RawStatus(answer), 204) << answer;
  const SeenHead seen = TakeSeen();
  EXPECT_EQ(seen.socket_local_port, port_);
  EXPECT_EQ(seen.socket_peer_port, client_port);
  EXPECT_EQ(seen.size.header_count, 2u);
  EXPECT_EQ(seen.size.target_bytes, 1u);
}

TEST_F(MhdRequestTest, AnIpv6PeerIsWrittenInBrackets) {
  if (!StartDaemon(/*ipv6=*/true)) GTEST_SKIP() << "no IPv6 loopback here";
  int client_port = 0;
  const std::string answer =
      RawHttpExchange(port_, "GET /healthz HTTP/1.1\r\nHost: [::1]\r\nConnection: close\r\n\r\n",
                      true, &client_port);
  ASSERT_EQ(RawStatus(answer), 204) << answer;
  EXPECT_EQ(TakeSeen().request.peer, absl::StrCat("[::1]:", client_port));
}

}  // namespace
}  // namespace ispq::server::http
