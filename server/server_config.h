// SPDX-License-Identifier: Apache-2.0
// Everything ispq-server is configured with, as one value: filled from the command-line flags
// by server_main.cc and checked once before anything starts.
#ifndef ISPQ_SERVER_SERVER_CONFIG_H_
#define ISPQ_SERVER_SERVER_CONFIG_H_

#include <cstdint>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/time/time.h"
#include "server/auth/principal_tokens.h"

namespace ispq::server {

// PEM files. cert and key together enable TLS; client_ca additionally requires and verifies
// client certificates signed by that CA (mutual TLS).
struct TlsFiles {
  std::string cert;
  std::string key;
  std::string client_ca;

  bool enabled() const { return !cert.empty(); }
};

struct ServerConfig {
  std::string listen_address = "127.0.0.1:50051";
  int workers = 1;
  int max_message_bytes = 32 << 20;
  int max_arcs = 2000000;
  // UploadMesh (server/grpc/mesh_upload.h): the largest mesh it takes, and how long it waits for
  // the next chunk before dropping the upload.
  int64_t max_upload_bytes = int64_t{1} << 30;
  absl::Duration upload_idle = absl::Seconds(60);
  int max_queued_jobs = 64;
  absl::Duration max_job_time = absl::Minutes(10);  // InfiniteDuration: no server limit
  int retain_finished_jobs = 1000;
  absl::Duration retain_finished_time = absl::Hours(1);
  int max_stored_meshes = 100;
  int64_t max_memory_bytes = int64_t{1} << 30;  // the memory budget (server/memory/memory_budget.h)
  int admission_threads = 1;                    // server/admission/admission_pool.h
  int max_waiting_admissions = 64;
  absl::Duration shutdown_grace = absl::Seconds(25);
  TlsFiles tls;
  std::vector<PrincipalToken> auth_tokens;    // empty: no bearer-token check
  std::vector<std::string> admin_principals;  // server/auth/authenticator.h
  // "memory" (server/store/in_memory_job_store.h) or a postgresql:// URI
  // (server/store/postgres/postgres_job_store.h), shared by the replicas that use the same
  // database.
  std::string job_store = "memory";
  absl::Duration job_lease = absl::Seconds(30);  // with PostgreSQL: a claimed job's lease
  // With PostgreSQL: the longest one database operation may take.
  absl::Duration job_store_timeout = absl::Seconds(10);
  // Connections older than this are asked to reconnect (GOAWAY), so that clients re-resolve and
  // spread over new replicas; zero: never. Streams in progress get the job time limit plus a
  // minute to finish.
  absl::Duration max_connection_age = absl::Minutes(5);
  std::string http_listen_address;  // empty: no HTTP side (server/http/)
  int http_max_event_streams = 32;
  // Host header values the HTTP side answers (server/http/origin_policy.h); empty: its defaults.
  std::vector<std::string> http_allowed_hosts;
  // The HTTP side's own certificate and key (HTTPS); both empty: gRPC's (tls) if it has them.
  std::string http_tls_cert;
  std::string http_tls_key;
  // Plaintext HTTP even when gRPC uses TLS: behind a TLS-terminating proxy, or on a trusted
  // network.
  bool http_plaintext = false;
};

// The certificate and key the HTTP side serves HTTPS with: --http_tls_cert and --http_tls_key,
// else gRPC's --tls_cert and --tls_key, so that one certificate protects both sides by default;
// none (plaintext) with --http_plaintext, without --http_listen, or when neither is set.
TlsFiles HttpTlsFiles(const ServerConfig& config);

// INVALID_ARGUMENT naming the flag for values that cannot work.
absl::Status ValidateServerConfig(const ServerConfig& config);

}  // namespace ispq::server

#endif  // ISPQ_SERVER_SERVER_CONFIG_H_
