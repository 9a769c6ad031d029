// SPDX-License-Identifier: Apache-2.0
// MakeServerCredentials (server/server_credentials.h): plaintext without TLS files; with them,
// a file that cannot be used stops the server at start with an error naming that file, so that
// an operator knows which one to fix. (TLS and mutual TLS with real certificates are tested on
// the server process in tests/integration/security_test.cc.)
#include "server/server_credentials.h"

#include <stdlib.h>

#include <fstream>
#include <memory>
#include <string>

#include "gmock/gmock.h"
#include "grpcpp/grpcpp.h"
#include "gtest/gtest.h"
#include "ispq/v1/service.grpc.pb.h"

namespace ispq::server {
namespace {

using ::testing::HasSubstr;

// A file of `bytes` bytes in a fresh temporary directory.
std::string WriteFile(const std::string& name, size_t bytes) {
  std::string directory = ::testing::TempDir() + "ispq-credentials-XXXXXX";
  EXPECT_NE(mkdtemp(directory.data()), nullptr);
  const std::string path = directory + "/" + name;
  std::ofstream(path) << std::string(bytes, '-');
  return path;
}

TEST(ServerCredentialsTest, WithoutTlsFilesTheListenerIsPlaintext) {
  const absl::StatusOr<std::shared_ptr<grpc::ServerCredentials>> credentials =
      MakeServerCredentials(TlsFiles());
  ASSERT_TRUE(credentials.ok()) << credentials.status();
  ASSERT_NE(*credentials, nullptr);
  int port = 0;
  v1::Quantizer::Service unimplemented;  // answers every method UNIMPLEMENTED
  grpc::ServerBuilder builder;
  builder.AddListeningPort("127.0.0.1:0", *credentials, &port);
  builder.RegisterService(&unimplemented);
  const std::unique_ptr<grpc::Server> server = builder.BuildAndStart();
  ASSERT_NE(server, nullptr);
  ASSERT_GT(port, 0);
  const std::shared_ptr<grpc::Channel> channel =
      grpc::CreateChannel("127.0.0.1:" + std::to_string(port), grpc::InsecureChannelCredentials());
  grpc::ClientContext context;
  v1::ServerStats stats;
  const grpc::Status status = v1::Quantizer::NewStub(channel)->GetServerStats(
      &context, v1::GetServerStatsRequest(), &stats);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::UNIMPLEMENTED)
      << "a plaintext call reaches the server: " << status.error_message();
  server->Shutdown();
}

TEST(ServerCredentialsTest, AFileThatCannotBeReadIsNamed) {
  const std::string cert = WriteFile("server.crt", 100);
  const std::string key = WriteFile("server.key", 100);
  const std::string missing = ::testing::TempDir() + "ispq-no-such-file.pem";
  struct Case {
    TlsFiles tls;
    std::string named;
  };
  for (const Case& bad : {Case{{.cert = missing, .key = key, .client_ca = ""}, missing},
                          Case{{.cert = cert, .key = missing, .client_ca = ""}, missing},
                          Case{{.cert = cert, .key = key, .client_ca = missing}, missing}}) {
    const absl::Status status = MakeServerCredentials(bad.tls).status();
    EXPECT_EQ(status.code(), absl::StatusCode::kNotFound) << status;
    EXPECT_THAT(std::string(status.message()), HasSubstr(bad.named));
  }
}

// PEM files are small; a huge one (a wrong path to a large file, a device) is refused before it
// is read whole.
TEST(ServerCredentialsTest, AFileTooLargeForPemIsInvalidArgumentNamingIt) {
  const std::string cert = WriteFile("server.crt", 100);
  const std::string key = WriteFile("server.key", 100);
  const std::string huge = WriteFile("huge.pem", (1 << 20) + 1);
  for (const TlsFiles& tls : {TlsFiles{.cert = huge, .key = key, .client_ca = ""},
                              TlsFiles{.cert = cert, .key = huge, .client_ca = ""},
                              TlsFiles{.cert = cert, .key = key, .client_ca = huge}}) {
    const absl::Status status = MakeServerCredentials(tls).status();
    EXPECT_EQ(status.code(), absl::StatusCode::kInvalidArgument) << status;
    EXPECT_THAT(std::string(status.message()), HasSubstr(huge));
  }
}

}  // namespace
}  // namespace ispq::server
