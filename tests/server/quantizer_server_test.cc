// SPDX-License-Identifier: Apache-2.0
// QuantizerServer (server/quantizer_server.h) in this process, for what the process tests
// (tests/integration) do not reach: a start that fails after the workers are up, because the
// gRPC address or the HTTP address cannot be bound or another server listens on it, returns
// UNAVAILABLE naming the address and leaves nothing running (no crash, no hang, in the destructor
// or the shutdown). A server that starts serves and shuts down as the process tests show.
#include "server/quantizer_server.h"

#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <string>

#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace ispq::server {
namespace {

using ::testing::HasSubstr;

// A loopback TCP port held by a listening socket without SO_REUSEPORT, which nothing else can
// bind; closed with the object.
class HeldPort {
 public:
  HeldPort() : socket_(::socket(AF_INET, SOCK_STREAM, 0)) {
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    address.sin_port = 0;
    EXPECT_EQ(bind(socket_, reinterpret_cast<sockaddr*>(&address), sizeof(address)), 0);
    EXPECT_EQ(listen(socket_, 1), 0);
    socklen_t size = sizeof(address);
    EXPECT_EQ(getsockname(socket_, reinterpret_cast<sockaddr*>(&address), &size), 0);
    port_ = ntohs(address.sin_port);
  }
  ~HeldPort() { close(socket_); }
  HeldPort(const HeldPort&) = delete;
  HeldPort& operator=(const HeldPort&) = delete;

  std::string address() const { return "127.0.0.1:" + std::to_string(port_); }

 private:
  const int socket_;
  int port_ = 0;
};

TEST(QuantizerServerTest, AGrpcAddressThatCannotBeBoundIsUnavailable) {
  const HeldPort held;
  ServerConfig config;
  config.listen_address = held.address();
  const absl::StatusOr<std::unique_ptr<QuantizerServer>> server = QuantizerServer::Start(config);
  EXPECT_EQ(server.status().code(), absl::StatusCode::kUnavailable);
  EXPECT_THAT(std::string(server.status().message()), HasSubstr(held.address()));
}

TEST(QuantizerServerTest, AnHttpAddressThatCannotBeBoundStopsTheStartedGrpcServer) {
  const HeldPort held;
  ServerConfig config;
  config.listen_address = "127.0.0.1:0";
  config.http_listen_address = held.address();
  const absl::StatusOr<std::unique_ptr<QuantizerServer>> server = QuantizerServer::Start(config);
  EXPECT_EQ(server.status().code(), absl::StatusCode::kUnavailable);
  EXPECT_THAT(std::string(server.status().message()), HasSubstr(held.address()));
}

// gRPC lets sockets share a port (SO_REUSEPORT) by default: a second server started by mistake
// with a running one's address would take half of its connections, and with jobs kept in each
// process's memory a client would find its job on one and NOT_FOUND on the other. A busy address
// is refused instead, as the HTTP side refuses it.
TEST(QuantizerServerTest, AnAddressAnotherServerListensOnIsUnavailable) {
  ServerConfig config;
  config.listen_address = "127.0.0.1:0";
  const absl::StatusOr<std::unique_ptr<QuantizerServer>> first = QuantizerServer::Start(config);
  ASSERT_TRUE(first.ok()) << first.status();
  config.listen_address = "127.0.0.1:" + std::to_string((*first)->port());
  const absl::StatusOr<std::unique_ptr<QuantizerServer>> second = QuantizerServer::Start(config);
  EXPECT_EQ(second.status().code(), absl::StatusCode::kUnavailable)
      << "a second server listens on " << config.listen_address;
}

}  // namespace
}  // namespace ispq::server
