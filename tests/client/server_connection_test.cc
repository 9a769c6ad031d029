// SPDX-License-Identifier: Apache-2.0
// How the client turns its connection options into a channel, without a server: address lists
// become ipv4:/ipv6: targets while URIs and single addresses pass through; TLS is on with any TLS
// option; and unusable options (no address, an unknown balancing policy, half a client
// certificate, a CA file that is not there) are refused before any channel exists.
#include "client/server_connection.h"

#include <string>

#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "tests/client/client_test_files.h"

namespace ispq::client {
namespace {

using ::testing::HasSubstr;

TEST(ServerConnectionTest, AddressListsBecomeAddressTargets) {
  EXPECT_EQ(ChannelTarget("10.0.0.1:50051,10.0.0.2:50051"), "ipv4:10.0.0.1:50051,10.0.0.2:50051");
  EXPECT_EQ(ChannelTarget("[::1]:50051,[::2]:50051"), "ipv6:[::1]:50051,[::2]:50051");
}

TEST(ServerConnectionTest, AnAddressListIsAddressedAsItsFirstAddress) {
  EXPECT_EQ(ChannelAuthority("10.0.0.1:50051,10.0.0.2:50051"), "10.0.0.1:50051");
  EXPECT_EQ(ChannelAuthority("ipv4:10.0.0.1:1,10.0.0.2:2"), "10.0.0.1:1");
  EXPECT_EQ(ChannelAuthority("[::1]:50051,[::2]:50051"), "[::1]:50051");
  EXPECT_EQ(ChannelAuthority("ipv6:[::1]:1,[::2]:2"), "[::1]:1");
  for (const std::string target :
       {"127.0.0.1:50051", "localhost:50051", "dns:///ispq.svc:50051", "ipv4:10.0.0.1:1"}) {
    EXPECT_EQ(ChannelAuthority(target), "") << target;
  }
}

TEST(ServerConnectionTest, SingleAddressesAndUrisPassThrough) {
  for (const std::string target :
       {"127.0.0.1:50051", "localhost:50051", "[::1]:50051", "dns:///ispq.svc:50051",
        "ipv4:10.0.0.1:1,10.0.0.2:2", "ipv6:[::1]:1,[::2]:2", "dns://8.8.8.8/a:1,b:2"}) {
    EXPECT_EQ(ChannelTarget(target), target);
  }
}

TEST(ServerConnectionTest, AnyTlsOptionTurnsTlsOn) {
  ServerConnection connection;
  EXPECT_FALSE(connection.uses_tls());
  connection.tls = true;
  EXPECT_TRUE(connection.uses_tls());
  for (std::string ServerConnection::*file :
       {&ServerConnection::tls_ca_file, &ServerConnection::tls_cert_file,
        &ServerConnection::tls_key_file}) {
    ServerConnection with_file;
    with_file.*file = "x.pem";
    EXPECT_TRUE(with_file.uses_tls());
  }
}

TEST(ServerConnectionTest, UsableOptionsGiveAChannel) {
  ServerConnection connection;
  EXPECT_TRUE(OpenChannel(connection).ok());
  connection.address = "127.0.0.1:1,127.0.0.1:2";
  for (const char* policy : {"", "round_robin", "pick_first"}) {
    connection.lb_policy = policy;
    const absl::StatusOr<std::shared_ptr<grpc::Channel>> channel = OpenChannel(connection);
    ASSERT_TRUE(channel.ok()) << policy << ": " << channel.status();
    EXPECT_NE(*channel, nullptr);
  }
  ServerConnection tls;
  tls.tls = true;  // the system's roots
  EXPECT_TRUE(OpenChannel(tls).ok());
}

TEST(ServerConnectionTest, UnusableOptionsAreRefused) {
  ServerConnection no_address;
  no_address.address = "";
  EXPECT_EQ(OpenChannel(no_address).status().message(), "no server address given");

  ServerConnection policy;
  policy.lb_policy = "random";
  EXPECT_EQ(OpenChannel(policy).status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(OpenChannel(policy).status().message()),
              HasSubstr("\"random\" is not one of round_robin, pick_first"));

  const testing::TestFolder folder;
  ServerConnection half_cert;
  half_cert.tls_cert_file = folder.Write("cert.pem", "x");
  EXPECT_EQ(OpenChannel(half_cert).status().message(),
            "a client certificate needs both --tls_cert and --tls_key");
  ServerConnection half_key;
  half_key.tls_key_file = folder.Write("key.pem", "x");
  EXPECT_EQ(OpenChannel(half_key).status().code(), absl::StatusCode::kInvalidArgument);

  ServerConnection missing_ca;
  missing_ca.tls_ca_file = folder.Path("missing-ca.pem");
  EXPECT_EQ(OpenChannel(missing_ca).status().code(), absl::StatusCode::kNotFound);
  EXPECT_THAT(std::string(OpenChannel(missing_ca).status().message()), HasSubstr("missing-ca.pem"));
  ServerConnection missing_key;
  missing_key.tls_cert_file = folder.Write("cert.pem", "x");
  missing_key.tls_key_file = folder.Path("missing-key.pem");
  EXPECT_EQ(OpenChannel(missing_key).status().code(), absl::StatusCode::kNotFound);
}

}  // namespace
}  // namespace ispq::client
