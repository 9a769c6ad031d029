// SPDX-License-Identifier: Apache-2.0
// Transport security and the bearer token: TLS with the server's certificate, mutual TLS that
// requires a client certificate, and the token check on the Quantizer methods, with health
// checking left open for orchestrators. Certificates are made fresh with openssl for each test.
#include <memory>
#include <string>

#include "client/health_check.h"
#include "client/server_connection.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "tests/integration/service_test_support.h"
#include "tests/support/run_command.h"

namespace ispq::testing {
namespace {

using ::testing::HasSubstr;

// A self-signed certificate for localhost and 127.0.0.1 (it is its own CA, so it also serves to
// verify itself as a client certificate).
struct Certificate {
  std::string cert_file;
  std::string key_file;
};

Certificate MakeCertificate(const std::string& directory, const std::string& name) {
  const Certificate certificate = {directory + "/" + name + ".crt",
                                   directory + "/" + name + ".key"};
  const CommandResult made = RunCommand(
      "openssl req -x509 -newkey rsa:2048 -nodes -days 2 -subj /CN=localhost"
      " -addext subjectAltName=DNS:localhost,IP:127.0.0.1 -keyout " +
      certificate.key_file + " -out " + certificate.cert_file);
  EXPECT_EQ(made.exit_code, 0) << made.output;
  return certificate;
}

std::string TemporaryDirectory() {
  std::string pattern = ::testing::TempDir() + "ispq-tls-XXXXXX";
  EXPECT_NE(mkdtemp(pattern.data()), nullptr);
  return pattern;
}

absl::StatusOr<v1::ServerStats> StatsVia(const client::ServerConnection& connection) {
  absl::StatusOr<client::QuantizerClient> client = client::QuantizerClient::Connect(connection);
  if (!client.ok()) return client.status();
  return client->GetServerStats();
}

TEST(SecurityTest, BearerTokenGuardsTheServiceButNotHealth) {
  const std::string directory = TemporaryDirectory();
  const std::string token_file = directory + "/token";
  ASSERT_EQ(RunCommand("printf 's3cret-token\\n' > " + token_file).exit_code, 0);
  std::unique_ptr<ServerProcess> server = StartServerOrFail({"--auth_token_file=" + token_file});
  ASSERT_NE(server, nullptr);

  client::QuantizerClient anonymous = ClientOf(*server);
  const absl::StatusOr<v1::Job> refused = anonymous.SubmitJob(RequestFor(NotchMesh(), 100));
  EXPECT_EQ(refused.status().code(), absl::StatusCode::kUnauthenticated);
  EXPECT_THAT(std::string(refused.status().message()), HasSubstr("bearer token"));
  const client::JobOutcome streamed =
      anonymous.Quantize(RequestFor(NotchMesh(), 100), StreamFor(kJobTimeout));
  EXPECT_EQ(streamed.status.code(), absl::StatusCode::kUnauthenticated);
  EXPECT_EQ(anonymous.GetServerStats().status().code(), absl::StatusCode::kUnauthenticated);
  EXPECT_EQ(ClientOf(*server, "wrong-token").GetServerStats().status().code(),
            absl::StatusCode::kUnauthenticated);
  EXPECT_EQ(ClientOf(*server, "s3cret-token-and-more").GetServerStats().status().code(),
            absl::StatusCode::kUnauthenticated);

  const absl::StatusOr<client::ServingStatus> health =
      client::CheckHealth(anonymous.channel(), "", absl::Seconds(30));
  ASSERT_TRUE(health.ok()) << health.status();
  EXPECT_EQ(*health, client::ServingStatus::kServing);

  client::QuantizerClient authorized = ClientOf(*server, "s3cret-token");
  const client::JobOutcome outcome =
      authorized.Quantize(RequestFor(NotchMesh(), 100), StreamFor(kJobTimeout));
  ASSERT_TRUE(outcome.status.ok()) << outcome.status;
  EXPECT_TRUE(IsValidResult(NotchMesh(), *outcome.result));
}

TEST(SecurityTest, TlsWithTheServerCertificate) {
  const std::string directory = TemporaryDirectory();
  const Certificate server_certificate = MakeCertificate(directory, "server");
  std::unique_ptr<ServerProcess> server = StartServerOrFail(
      {"--tls_cert=" + server_certificate.cert_file, "--tls_key=" + server_certificate.key_file});
  ASSERT_NE(server, nullptr);

  client::ServerConnection connection;
  connection.address = "localhost:" + std::to_string(server->port());
  connection.tls_ca_file = server_certificate.cert_file;
  absl::StatusOr<client::QuantizerClient> client = client::QuantizerClient::Connect(connection);
  ASSERT_TRUE(client.ok()) << client.status();
  const client::JobOutcome outcome =
      client->Quantize(RequestFor(NotchMesh(), 100), StreamFor(kJobTimeout));
  ASSERT_TRUE(outcome.status.ok()) << outcome.status;
  EXPECT_TRUE(IsValidResult(NotchMesh(), *outcome.result));

  client::ServerConnection plaintext;
  plaintext.address = connection.address;
  EXPECT_EQ(StatsVia(plaintext).status().code(), absl::StatusCode::kUnavailable);
  client::ServerConnection untrusted = connection;
  untrusted.tls_ca_file = MakeCertificate(directory, "other").cert_file;
  EXPECT_EQ(StatsVia(untrusted).status().code(), absl::StatusCode::kUnavailable);
}

TEST(SecurityTest, MutualTlsRequiresAClientCertificate) {
  const std::string directory = TemporaryDirectory();
  const Certificate server_certificate = MakeCertificate(directory, "server");
  const Certificate client_certificate = MakeCertificate(directory, "client");
  std::unique_ptr<ServerProcess> server = StartServerOrFail(
      {"--tls_cert=" + server_certificate.cert_file, "--tls_key=" + server_certificate.key_file,
       "--tls_client_ca=" + client_certificate.cert_file});
  ASSERT_NE(server, nullptr);

  client::ServerConnection connection;
  connection.address = "localhost:" + std::to_string(server->port());
  connection.tls_ca_file = server_certificate.cert_file;
  EXPECT_EQ(StatsVia(connection).status().code(), absl::StatusCode::kUnavailable)
      << "no client certificate";
  client::ServerConnection wrong_client = connection;
  wrong_client.tls_cert_file = server_certificate.cert_file;  // not signed by the client CA
  wrong_client.tls_key_file = server_certificate.key_file;
  EXPECT_EQ(StatsVia(wrong_client).status().code(), absl::StatusCode::kUnavailable);

  connection.tls_cert_file = client_certificate.cert_file;
  connection.tls_key_file = client_certificate.key_file;
  const absl::StatusOr<v1::ServerStats> stats = StatsVia(connection);
  ASSERT_TRUE(stats.ok()) << stats.status();
  EXPECT_GE(stats->workers(), 1);
}

TEST(SecurityTest, UnusableTlsFilesStopTheServerAtStart) {
  const absl::StatusOr<std::unique_ptr<ServerProcess>> server = ServerProcess::Start(
      ServerBinaryPath(), {"--tls_cert=/nonexistent.crt", "--tls_key=/nonexistent.key"});
  ASSERT_FALSE(server.ok());
  EXPECT_THAT(std::string(server.status().message()), HasSubstr("/nonexistent.crt"));
  const absl::StatusOr<std::unique_ptr<ServerProcess>> half =
      ServerProcess::Start(ServerBinaryPath(), {"--tls_cert=/nonexistent.crt"});
  ASSERT_FALSE(half.ok());
  EXPECT_THAT(std::string(half.status().message()),
              HasSubstr("--tls_cert and --tls_key go together"));
}

}  // namespace
}  // namespace ispq::testing
