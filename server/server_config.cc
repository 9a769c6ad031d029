// SPDX-License-Identifier: Apache-2.0
#include "server/server_config.h"

#include "absl/strings/str_cat.h"
#include "server/http/origin_policy.h"

namespace ispq::server {
namespace {

// Below this, the server could not even take one request of the default maximum size.
constexpr int64_t kMinMemoryBytes = 64 << 20;
// Protobuf parses at most 2 GiB - 1 bytes in one message (the mesh and its framing).
constexpr int64_t kMaxUploadBytes = (int64_t{1} << 31) - 64;

absl::Status AtLeast(const char* flag, int64_t value, int64_t minimum) {
  if (value >= minimum) return absl::OkStatus();
  return absl::InvalidArgumentError(
      absl::StrCat("--", flag, " must be at least ", minimum, ", got ", value));
}

}  // namespace

absl::Status ValidateServerConfig(const ServerConfig& config) {
  if (config.listen_address.empty()) return absl::InvalidArgumentError("--listen is empty");
  for (const absl::Status& status : {
           AtLeast("workers", config.workers, 1),
           AtLeast("max_message_bytes", config.max_message_bytes, 1024),
           AtLeast("max_arcs", config.max_arcs, 1),
           AtLeast("max_queued_jobs", config.max_queued_jobs, 1),
           AtLeast("retain_finished_jobs", config.retain_finished_jobs, 0),
           AtLeast("max_stored_meshes", config.max_stored_meshes, 1),
           AtLeast("max_memory_bytes", config.max_memory_bytes, kMinMemoryBytes),
           AtLeast("admission_threads", config.admission_threads, 1),
           AtLeast("max_waiting_admissions", config.max_waiting_admissions, 1),
           AtLeast("http_max_event_streams", config.http_max_event_streams, 1),
       }) {
    if (!status.ok()) return status;
  }
  for (const std::string& host : config.http_allowed_hosts) {
    if (absl::Status valid = http::ValidateAllowedHost(host); !valid.ok()) return valid;
  }
  if (config.max_upload_bytes < 1 || config.max_upload_bytes > kMaxUploadBytes) {
    return absl::InvalidArgumentError(absl::StrCat(
        "--max_upload_bytes must be in [1, ", kMaxUploadBytes, "], got ", config.max_upload_bytes));
  }
  if (config.upload_idle <= absl::ZeroDuration()) {
    return absl::InvalidArgumentError("--upload_idle_seconds must be positive");
  }
  if (config.max_job_time <= absl::ZeroDuration()) {
    return absl::InvalidArgumentError("--max_job_seconds must be positive");
  }
  if (config.retain_finished_time < absl::ZeroDuration()) {
    return absl::InvalidArgumentError("--retain_seconds must not be negative");
  }
  if (config.shutdown_grace < absl::ZeroDuration()) {
    return absl::InvalidArgumentError("--shutdown_grace_seconds must not be negative");
  }
  if (config.tls.cert.empty() != config.tls.key.empty()) {
    return absl::InvalidArgumentError("--tls_cert and --tls_key go together");
  }
  if (!config.tls.client_ca.empty() && !config.tls.enabled()) {
    return absl::InvalidArgumentError("--tls_client_ca needs --tls_cert and --tls_key");
  }
  if (config.http_tls_cert.empty() != config.http_tls_key.empty()) {
    return absl::InvalidArgumentError("--http_tls_cert and --http_tls_key go together");
  }
  if (config.http_listen_address.empty() &&
      (!config.http_tls_cert.empty() || config.http_plaintext)) {
    return absl::InvalidArgumentError(
        absl::StrCat(config.http_plaintext ? "--http_plaintext" : "--http_tls_cert",
                     " needs --http_listen (the HTTP side is off without it)"));
  }
  if (config.http_plaintext && !config.http_tls_cert.empty()) {
    return absl::InvalidArgumentError(
        "--http_plaintext excludes --http_tls_cert and --http_tls_key");
  }
  if (config.job_store != "memory" && config.job_store.rfind("postgresql://", 0) != 0 &&
      config.job_store.rfind("postgres://", 0) != 0) {
    return absl::InvalidArgumentError(
        "--job_store must be \"memory\" or a postgresql://... connection URI");
  }
  if (config.job_lease < absl::Milliseconds(300)) {
    return absl::InvalidArgumentError("--job_lease_seconds must be at least 0.3");
  }
  if (config.job_store_timeout < absl::Milliseconds(100)) {
    return absl::InvalidArgumentError("--job_store_timeout_seconds must be at least 0.1");
  }
  if (config.max_connection_age < absl::ZeroDuration()) {
    return absl::InvalidArgumentError("--max_connection_age_seconds must not be negative");
  }
  return absl::OkStatus();
}

TlsFiles HttpTlsFiles(const ServerConfig& config) {
  if (config.http_listen_address.empty() || config.http_plaintext) return TlsFiles();
  if (!config.http_tls_cert.empty()) {
    return TlsFiles{.cert = config.http_tls_cert, .key = config.http_tls_key, .client_ca = ""};
  }
  // Not gRPC's client CA: the HTTP side asks browsers for no certificate (tokens name principals).
  return TlsFiles{.cert = config.tls.cert, .key = config.tls.key, .client_ca = ""};
}

}  // namespace ispq::server
