// SPDX-License-Identifier: Apache-2.0
// ValidateServerConfig (server/server_config.h): the defaults start a server; every value that
// cannot work is INVALID_ARGUMENT naming the command-line flag to fix, and the smallest values that
// can work are accepted.
#include "server/server_config.h"

#include <functional>
#include <string>
#include <vector>

#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace ispq::server {
namespace {

using ::testing::HasSubstr;

struct BadValue {
  std::string flag;  // what the message must name
  std::function<void(ServerConfig&)> change;
};

std::vector<BadValue> BadValues() {
  return {
      {"--listen", [](ServerConfig& c) { c.listen_address.clear(); }},
      {"--workers", [](ServerConfig& c) { c.workers = 0; }},
      {"--max_message_bytes", [](ServerConfig& c) { c.max_message_bytes = 1023; }},
      {"--max_arcs", [](ServerConfig& c) { c.max_arcs = 0; }},
      {"--max_queued_jobs", [](ServerConfig& c) { c.max_queued_jobs = 0; }},
      {"--retain_finished_jobs", [](ServerConfig& c) { c.retain_finished_jobs = -1; }},
      {"--max_stored_meshes", [](ServerConfig& c) { c.max_stored_meshes = 0; }},
      {"--max_memory_bytes", [](ServerConfig& c) { c.max_memory_bytes = (64 << 20) - 1; }},
      {"--admission_threads", [](ServerConfig& c) { c.admission_threads = 0; }},
      {"--max_waiting_admissions", [](ServerConfig& c) { c.max_waiting_admissions = 0; }},
      {"--http_max_event_streams", [](ServerConfig& c) { c.http_max_event_streams = 0; }},
      {"--http_allowed_hosts",
       [](ServerConfig& c) {
         c.http_allowed_hosts = {"ok", "bad host"};
       }},
      {"--max_job_seconds", [](ServerConfig& c) { c.max_job_time = absl::ZeroDuration(); }},
      {"--retain_seconds", [](ServerConfig& c) { c.retain_finished_time = -absl::Seconds(1); }},
      {"--shutdown_grace_seconds",
       [](ServerConfig& c) { c.shutdown_grace = -absl::Milliseconds(1); }},
      {"--tls_key", [](ServerConfig& c) { c.tls.cert = "server.crt"; }},
      {"--tls_cert", [](ServerConfig& c) { c.tls.key = "server.key"; }},
      {"--tls_client_ca", [](ServerConfig& c) { c.tls.client_ca = "ca.crt"; }},
      {"--job_store", [](ServerConfig& c) { c.job_store = "mysql://db/ispq"; }},
      {"--job_store", [](ServerConfig& c) { c.job_store = ""; }},
      {"--job_lease_seconds", [](ServerConfig& c) { c.job_lease = absl::Milliseconds(299); }},
      {"--job_store_timeout_seconds",
       [](ServerConfig& c) { c.job_store_timeout = absl::Milliseconds(99); }},
      {"--max_connection_age_seconds",
       [](ServerConfig& c) { c.max_connection_age = -absl::Seconds(1); }},
      {"--http_tls_key",
       [](ServerConfig& c) {
         c.http_listen_address = "127.0.0.1:0";
         c.http_tls_cert = "http.crt";
       }},
      {"--http_tls_cert",
       [](ServerConfig& c) {
         c.http_listen_address = "127.0.0.1:0";
         c.http_tls_key = "http.key";
       }},
      {"--http_listen",  // an HTTP certificate for no HTTP side is a mistake worth naming
       [](ServerConfig& c) {
         c.http_tls_cert = "http.crt";
         c.http_tls_key = "http.key";
       }},
      {"--http_listen", [](ServerConfig& c) { c.http_plaintext = true; }},
      {"--http_plaintext",
       [](ServerConfig& c) {
         c.http_listen_address = "127.0.0.1:0";
         c.http_tls_cert = "http.crt";
         c.http_tls_key = "http.key";
         c.http_plaintext = true;
       }},
  };
}

TEST(ServerConfigTest, TheDefaultsAreValid) {
  const absl::Status status = ValidateServerConfig(ServerConfig());
  EXPECT_TRUE(status.ok()) << status;
}

TEST(ServerConfigTest, EachValueThatCannotWorkNamesItsFlag) {
  for (const BadValue& bad : BadValues()) {
    SCOPED_TRACE(bad.flag);
    ServerConfig config;
    bad.change(config);
    const absl::Status status = ValidateServerConfig(config);
    EXPECT_EQ(status.code(), absl::StatusCode::kInvalidArgument) << status;
    EXPECT_THAT(std::string(status.message()), HasSubstr(bad.flag));
  }
}

TEST(ServerConfigTest, AMinimumIsSaidWithTheValueGiven) {
  ServerConfig config;
  config.max_queued_jobs = -3;
  EXPECT_EQ(ValidateServerConfig(config).message(), "--max_queued_jobs must be at least 1, got -3");
}

// The smallest values that work, and the values that switch a limit off.
TEST(ServerConfigTest, TheLimitsThemselvesAreAccepted) {
  ServerConfig config;
  config.workers = 1;
  config.max_message_bytes = 1024;
  config.max_arcs = 1;
  config.max_queued_jobs = 1;
  config.retain_finished_jobs = 0;
  config.max_stored_meshes = 1;
  config.max_memory_bytes = 64 << 20;
  config.admission_threads = 1;
  config.max_waiting_admissions = 1;
  config.http_max_event_streams = 1;
  config.max_job_time = absl::InfiniteDuration();
  config.retain_finished_time = absl::ZeroDuration();
  config.shutdown_grace = absl::ZeroDuration();
  config.job_lease = absl::Milliseconds(300);
  config.job_store_timeout = absl::Milliseconds(100);
  config.max_connection_age = absl::ZeroDuration();
  config.http_allowed_hosts = {"*", "ispq.example.com:8080", "127.0.0.1"};
  const absl::Status status = ValidateServerConfig(config);
  EXPECT_TRUE(status.ok()) << status;
}

TEST(ServerConfigTest, TlsAndMutualTlsWithTheirFilesAreAccepted) {
  ServerConfig config;
  config.tls.cert = "server.crt";
  config.tls.key = "server.key";
  EXPECT_TRUE(ValidateServerConfig(config).ok());
  config.tls.client_ca = "ca.crt";
  EXPECT_TRUE(ValidateServerConfig(config).ok());
}

// The HTTP side is HTTPS with gRPC's certificate unless it has its own or is told to be plaintext;
// gRPC's client CA never carries over (the HTTP side asks for no client certificate).
TEST(ServerConfigTest, TheHttpSideUsesGrpcsCertificateByDefault) {
  ServerConfig config;
  config.tls = {.cert = "grpc.crt", .key = "grpc.key", .client_ca = "ca.crt"};
  EXPECT_FALSE(HttpTlsFiles(config).enabled()) << "no HTTP side, no HTTP certificate";
  config.http_listen_address = "[::]:8443";
  ASSERT_TRUE(ValidateServerConfig(config).ok());
  TlsFiles files = HttpTlsFiles(config);
  EXPECT_EQ(files.cert, "grpc.crt");
  EXPECT_EQ(files.key, "grpc.key");
  EXPECT_EQ(files.client_ca, "");

  config.http_tls_cert = "http.crt";
  config.http_tls_key = "http.key";
  ASSERT_TRUE(ValidateServerConfig(config).ok());
  files = HttpTlsFiles(config);
  EXPECT_EQ(files.cert, "http.crt");
  EXPECT_EQ(files.key, "http.key");

  config.http_tls_cert.clear();
  config.http_tls_key.clear();
  config.http_plaintext = true;
  ASSERT_TRUE(ValidateServerConfig(config).ok());
  EXPECT_FALSE(HttpTlsFiles(config).enabled());

  ServerConfig plaintext_grpc;
  plaintext_grpc.http_listen_address = "127.0.0.1:8080";
  EXPECT_FALSE(HttpTlsFiles(plaintext_grpc).enabled());
  plaintext_grpc.http_tls_cert = "http.crt";
  plaintext_grpc.http_tls_key = "http.key";
  ASSERT_TRUE(ValidateServerConfig(plaintext_grpc).ok());
  EXPECT_EQ(HttpTlsFiles(plaintext_grpc).cert, "http.crt") << "HTTPS without gRPC's TLS";
}

TEST(ServerConfigTest, EitherPostgresUriSchemeIsAJobStore) {
  ServerConfig config;
  for (const char* store : {"memory", "postgresql://ispq@db:5432/ispq", "postgres://db/ispq"}) {
    config.job_store = store;
    EXPECT_TRUE(ValidateServerConfig(config).ok()) << store;
  }
  // The scheme must lead: a URI that merely contains it is not one.
  config.job_store = "x-postgresql://db/ispq";
  EXPECT_EQ(ValidateServerConfig(config).code(), absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace ispq::server
