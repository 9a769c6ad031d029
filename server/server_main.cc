// SPDX-License-Identifier: Apache-2.0
// ispq-server: serves ispq.v1.Quantizer (see server/quantizer_server.h for the threading model
// and the shutdown sequence). Logs one structured line per event to stderr.
//
//   ispq-server [--listen 127.0.0.1:50051] [--workers N] [limits] [--max_memory_bytes SIZE]
//               [--tls_cert F --tls_key F [--tls_client_ca F]]
//               [--auth_token_file F | --auth_tokens_file F] [--admin_principals A,B]
//               [--http_listen HOST:PORT] [--http_allowed_hosts H1,H2:PORT]
//               [--http_tls_cert F --http_tls_key F | --http_plaintext]
//
// Stops gracefully on SIGTERM or SIGINT and exits 0; exits 1 if it cannot start.
#include <pthread.h>
#include <signal.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "absl/flags/flag.h"
#include "absl/flags/parse.h"
#include "absl/flags/usage.h"
#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/strip.h"
#include "core/large_allocations.h"
#include "core/read_file.h"
#include "server/auth/principal_tokens.h"
#include "server/logging/log_value.h"
#include "server/memory/memory_limit.h"
#include "server/quantizer_server.h"
#include "server/server_config.h"
#include "spdlog/sinks/stdout_sinks.h"
#include "spdlog/spdlog.h"

ABSL_FLAG(std::string, listen, "127.0.0.1:50051",
          "address to listen on, HOST:PORT; port 0 picks a free port (see --port_file); use "
          "0.0.0.0:PORT to accept connections from other hosts");
ABSL_FLAG(int, workers, 0, "jobs solved at once, one thread each; 0: one per hardware thread");
ABSL_FLAG(int, max_message_bytes, 32 << 20, "largest request accepted, in bytes");
ABSL_FLAG(int, max_arcs, 2000000,
          "largest T-mesh accepted, in arcs (the memory budget bounds what a mesh may cost)");
ABSL_FLAG(int64_t, max_upload_bytes, int64_t{1} << 30,
          "largest binary T-mesh accepted by UploadMesh (streamed in chunks), in bytes");
ABSL_FLAG(double, upload_idle_seconds, 60,
          "an UploadMesh that sends no chunk for this long is dropped and its memory released");
ABSL_FLAG(int, max_queued_jobs, 64,
          "jobs that may wait for a worker; beyond, requests get RESOURCE_EXHAUSTED");
ABSL_FLAG(double, max_job_seconds, 600,
          "time limit of every job (a request may ask for less); the job then returns its best "
          "valid quantization so far");
ABSL_FLAG(int, retain_finished_jobs, 1000, "finished jobs kept for GetJob/WatchJob");
ABSL_FLAG(double, retain_seconds, 3600, "how long a finished job is kept");
ABSL_FLAG(int, max_stored_meshes, 100,
          "meshes kept from CreateMesh; beyond, the least recently used is evicted");
ABSL_FLAG(std::string, max_memory_bytes, "",
          "memory budget for what the server holds for clients (requests being admitted, queued "
          "and running jobs, stored meshes, retained results), e.g. 512MiB or 2GiB; beyond it, "
          "requests get RESOURCE_EXHAUSTED after retained results and stored meshes are evicted. "
          "Default: 3/4 of the cgroup memory limit if there is one, else 1/2 of physical memory");
ABSL_FLAG(int, admission_threads, 0,
          "threads that parse and validate large requests off gRPC's threads; 0: half the "
          "hardware threads, at least 1");
ABSL_FLAG(double, shutdown_grace_seconds, 25,
          "time from SIGTERM to exit: running jobs may finish until a quarter of it (at most 5 s) "
          "is left, then they are interrupted and their results delivered");
ABSL_FLAG(std::string, tls_cert, "", "PEM certificate chain of the server; enables TLS");
ABSL_FLAG(std::string, tls_key, "", "PEM private key of --tls_cert");
ABSL_FLAG(std::string, tls_client_ca, "",
          "PEM CA certificates; if set, clients must present a certificate signed by one");
ABSL_FLAG(std::string, auth_token, "",
          "if set, every Quantizer call needs metadata 'authorization: Bearer <token>' (visible "
          "in the process list: prefer --auth_token_file)");
ABSL_FLAG(std::string, auth_token_file, "",
          "file holding the bearer token (e.g. a mounted secret); its principal is 'default'");
ABSL_FLAG(std::string, auth_tokens_file, "",
          "file of 'PRINCIPAL TOKEN' lines: several bearer tokens, each standing for a principal "
          "that owns the jobs and meshes it creates");
ABSL_FLAG(std::vector<std::string>, admin_principals, {},
          "principals (token principals or client-certificate subjects) that see and act on "
          "every job and mesh, comma-separated");
ABSL_FLAG(std::string, http_listen, "",
          "also serve HTTP on HOST:PORT (HTTPS with --http_tls_cert or --tls_cert, see "
          "--http_plaintext): the JSON API, job events as server-sent "
          "events, /metrics, /healthz, /readyz and the web view; empty: no HTTP side");
ABSL_FLAG(std::string, http_tls_cert, "",
          "PEM certificate chain of the HTTP side (HTTPS); default: --tls_cert, so that with TLS "
          "on gRPC the HTTP side is HTTPS too, with the same certificate");
ABSL_FLAG(std::string, http_tls_key, "", "PEM private key of --http_tls_cert; default: --tls_key");
ABSL_FLAG(bool, http_plaintext, false,
          "serve the HTTP side in plaintext even when gRPC uses TLS (behind a TLS-terminating "
          "proxy, or on a trusted network)");
ABSL_FLAG(std::string, http_port_file, "",
          "after binding, write the HTTP port to this file (with port 0 in --http_listen)");
ABSL_FLAG(int, http_max_event_streams, 32,
          "server-sent-event streams open at once on the HTTP side; beyond, 429");
ABSL_FLAG(std::vector<std::string>, http_allowed_hosts, {},
          "Host header values the HTTP side answers (against DNS rebinding), comma-separated: "
          "NAME (any port), NAME:PORT, [IPV6]:PORT, or * for any; others get 421 "
          "(/healthz, /readyz and /metrics answer any); default: the --http_listen host, "
          "localhost, 127.0.0.1 and [::1], each at the HTTP port");
ABSL_FLAG(std::string, port_file, "",
          "after binding, write the port to this file (for scripts that listen on port 0)");
ABSL_FLAG(std::string, log_level, "info", "trace, debug, info, warn, error or off");
ABSL_FLAG(std::string, job_store, "memory",
          "where jobs and stored meshes live: memory (this process), or a postgresql://... URI "
          "shared by several replicas; the URI may also come from $ISPQ_JOB_STORE");
ABSL_FLAG(double, job_lease_seconds, 30,
          "with PostgreSQL: how long a replica's claim on a running job lasts without renewal; "
          "a job whose replica died is run again elsewhere after at most this long");
ABSL_FLAG(double, job_store_timeout_seconds, 10,
          "with PostgreSQL: the longest one database operation may take before it fails with "
          "UNAVAILABLE (a database that hangs never holds a thread longer)");
ABSL_FLAG(double, max_connection_age_seconds, 300,
          "ask clients to reconnect after this long (0: never), so that they spread over new "
          "replicas");

namespace {

constexpr size_t kMaxTokenFileBytes = 1 << 20;

// The single token of --auth_token or --auth_token_file, if any.
absl::StatusOr<std::string> SingleAuthToken() {
  const std::string file = absl::GetFlag(FLAGS_auth_token_file);
  if (file.empty()) return absl::GetFlag(FLAGS_auth_token);
  if (!absl::GetFlag(FLAGS_auth_token).empty()) {
    return absl::InvalidArgumentError("--auth_token and --auth_token_file exclude each other");
  }
  absl::StatusOr<std::string> token = ispq::ReadFileToString(file, 4096);
  if (!token.ok()) return token.status();
  std::string trimmed(absl::StripAsciiWhitespace(*token));
  if (trimmed.empty()) return absl::InvalidArgumentError(absl::StrCat(file, " is empty"));
  return trimmed;
}

absl::StatusOr<std::vector<ispq::server::PrincipalToken>> AuthTokens() {
  absl::StatusOr<std::string> single = SingleAuthToken();
  if (!single.ok()) return single.status();
  const std::string file = absl::GetFlag(FLAGS_auth_tokens_file);
  if (file.empty()) {
    if (single->empty()) return std::vector<ispq::server::PrincipalToken>();
    return std::vector<ispq::server::PrincipalToken>{
        {ispq::server::kSingleTokenPrincipal, *std::move(single)}};
  }
  if (!single->empty()) {
    return absl::InvalidArgumentError(
        "--auth_tokens_file excludes --auth_token and --auth_token_file");
  }
  absl::StatusOr<std::string> contents = ispq::ReadFileToString(file, kMaxTokenFileBytes);
  if (!contents.ok()) return contents.status();
  absl::StatusOr<std::vector<ispq::server::PrincipalToken>> tokens =
      ispq::server::ParsePrincipalTokens(*contents);
  if (!tokens.ok()) {
    return absl::InvalidArgumentError(absl::StrCat(file, ": ", tokens.status().message()));
  }
  return tokens;
}

absl::StatusOr<int64_t> MaxMemoryBytes() {
  const std::string flag = absl::GetFlag(FLAGS_max_memory_bytes);
  if (flag.empty()) return ispq::server::DefaultMemoryBudget();
  absl::StatusOr<int64_t> bytes = ispq::server::ParseByteSize(flag);
  if (!bytes.ok()) {
    return absl::InvalidArgumentError(
        absl::StrCat("--max_memory_bytes: ", bytes.status().message()));
  }
  return bytes;
}

absl::StatusOr<ispq::server::ServerConfig> ConfigFromFlags() {
  ispq::server::ServerConfig config;
  config.listen_address = absl::GetFlag(FLAGS_listen);
  const int workers = absl::GetFlag(FLAGS_workers);
  config.workers = workers > 0 ? workers : std::max(1u, std::thread::hardware_concurrency());
  if (workers < 0) return absl::InvalidArgumentError("--workers must not be negative");
  config.max_message_bytes = absl::GetFlag(FLAGS_max_message_bytes);
  config.max_arcs = absl::GetFlag(FLAGS_max_arcs);
  config.max_upload_bytes = absl::GetFlag(FLAGS_max_upload_bytes);
  config.upload_idle = absl::Seconds(absl::GetFlag(FLAGS_upload_idle_seconds));
  config.max_queued_jobs = absl::GetFlag(FLAGS_max_queued_jobs);
  config.max_job_time = absl::Seconds(absl::GetFlag(FLAGS_max_job_seconds));
  config.retain_finished_jobs = absl::GetFlag(FLAGS_retain_finished_jobs);
  config.retain_finished_time = absl::Seconds(absl::GetFlag(FLAGS_retain_seconds));
  config.max_stored_meshes = absl::GetFlag(FLAGS_max_stored_meshes);
  absl::StatusOr<int64_t> memory = MaxMemoryBytes();
  if (!memory.ok()) return memory.status();
  config.max_memory_bytes = *memory;
  const int admission_threads = absl::GetFlag(FLAGS_admission_threads);
  if (admission_threads < 0) return absl::InvalidArgumentError("--admission_threads is negative");
  config.admission_threads = admission_threads > 0
                                 ? admission_threads
                                 : std::max(1u, std::thread::hardware_concurrency() / 2);
  config.shutdown_grace = absl::Seconds(absl::GetFlag(FLAGS_shutdown_grace_seconds));
  config.tls.cert = absl::GetFlag(FLAGS_tls_cert);
  config.tls.key = absl::GetFlag(FLAGS_tls_key);
  config.tls.client_ca = absl::GetFlag(FLAGS_tls_client_ca);
  absl::StatusOr<std::vector<ispq::server::PrincipalToken>> tokens = AuthTokens();
  if (!tokens.ok()) return tokens.status();
  config.auth_tokens = *std::move(tokens);
  config.admin_principals = absl::GetFlag(FLAGS_admin_principals);
  config.job_store = absl::GetFlag(FLAGS_job_store);
  // A URI with a password belongs in the environment (a Kubernetes Secret), not in argv.
  if (const char* from_environment = std::getenv("ISPQ_JOB_STORE");
      config.job_store == "memory" && from_environment != nullptr && *from_environment != '\0') {
    config.job_store = from_environment;
  }
  config.job_lease = absl::Seconds(absl::GetFlag(FLAGS_job_lease_seconds));
  config.job_store_timeout = absl::Seconds(absl::GetFlag(FLAGS_job_store_timeout_seconds));
  config.max_connection_age = absl::Seconds(absl::GetFlag(FLAGS_max_connection_age_seconds));
  config.http_listen_address = absl::GetFlag(FLAGS_http_listen);
  config.http_max_event_streams = absl::GetFlag(FLAGS_http_max_event_streams);
  config.http_allowed_hosts = absl::GetFlag(FLAGS_http_allowed_hosts);
  config.http_tls_cert = absl::GetFlag(FLAGS_http_tls_cert);
  config.http_tls_key = absl::GetFlag(FLAGS_http_tls_key);
  config.http_plaintext = absl::GetFlag(FLAGS_http_plaintext);
  return config;
}

// Written to a temporary name and renamed, so that a reader never sees a partial port.
absl::Status WritePortFile(const std::string& path, int port) {
  const std::string temporary = path + ".tmp";
  {
    std::ofstream out(temporary, std::ios::trunc);
    out << port << "\n";
    if (!out) return absl::InternalError(absl::StrCat("cannot write ", temporary));
  }
  std::error_code error;
  std::filesystem::rename(temporary, path, error);
  if (error) return absl::InternalError(absl::StrCat("cannot rename ", temporary, " to ", path));
  return absl::OkStatus();
}

}  // namespace

int main(int argc, char** argv) {
  ispq::MapLargeAllocationsSeparately();
  absl::SetProgramUsageMessage("ispq-server: the ispq quantization service (gRPC)");
  absl::ParseCommandLine(argc, argv);

  spdlog::set_default_logger(spdlog::stderr_logger_mt("ispq-server"));
  spdlog::set_pattern("ts=%Y-%m-%dT%H:%M:%S.%eZ level=%l %v", spdlog::pattern_time_type::utc);
  spdlog::set_level(spdlog::level::from_str(absl::GetFlag(FLAGS_log_level)));
  spdlog::flush_on(spdlog::level::info);

  // Block the stop signals in every thread (gRPC's and the workers inherit the mask) and take
  // them synchronously below, so that shutdown runs as ordinary code, not in a handler.
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGTERM);
  sigaddset(&stop_signals, SIGINT);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);

  absl::StatusOr<ispq::server::ServerConfig> config = ConfigFromFlags();
  if (!config.ok()) {
    spdlog::error("event=config_error error={}",
                  ispq::server::QuotedLogValue(std::string(config.status().message())));
    return 1;
  }
  absl::StatusOr<std::unique_ptr<ispq::server::QuantizerServer>> server =
      ispq::server::QuantizerServer::Start(*config);
  if (!server.ok()) {
    spdlog::error("event=start_error error={}",
                  ispq::server::QuotedLogValue(std::string(server.status().message())));
    return 1;
  }
  if (const std::string port_file = absl::GetFlag(FLAGS_port_file); !port_file.empty()) {
    if (absl::Status written = WritePortFile(port_file, (*server)->port()); !written.ok()) {
      spdlog::error("event=start_error error={}",
                    ispq::server::QuotedLogValue(std::string(written.message())));
      return 1;
    }
  }

  if (const std::string port_file = absl::GetFlag(FLAGS_http_port_file); !port_file.empty()) {
    if ((*server)->http_port() == 0) {
      spdlog::error("event=start_error error=\"--http_port_file needs --http_listen\"");
      return 1;
    }
    if (absl::Status written = WritePortFile(port_file, (*server)->http_port()); !written.ok()) {
      spdlog::error("event=start_error error={}",
                    ispq::server::QuotedLogValue(std::string(written.message())));
      return 1;
    }
  }

  int signal_number = 0;
  sigwait(&stop_signals, &signal_number);
  spdlog::info("event=signal signal={}", signal_number == SIGTERM ? "SIGTERM" : "SIGINT");
  (*server)->Shutdown();
  server->reset();
  spdlog::info("event=server_exit");
  return 0;
}
