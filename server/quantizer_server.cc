// SPDX-License-Identifier: Apache-2.0
#include "server/quantizer_server.h"

#include <algorithm>
#include <optional>
#include <utility>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "absl/time/clock.h"
#include "grpcpp/ext/proto_server_reflection_plugin.h"
#include "grpcpp/health_check_service_interface.h"
#include "grpcpp/server_builder.h"
#include "server/http/http_tls.h"
#include "server/server_credentials.h"
#include "server/store/postgres/postgres_job_store.h"
#include "server/store/postgres/postgres_mesh_store.h"
#include "spdlog/spdlog.h"

namespace ispq::server {
namespace {

// Part of the grace period kept for streams to deliver the terminal events of interrupted jobs.
constexpr absl::Duration kMaxFlushTime = absl::Seconds(5);

// HTTP/2 keepalive: a client that vanished without closing its connection is noticed within
// about this long, so a Quantize job bound to it gets cancelled instead of running on.
constexpr int kKeepaliveTimeMs = 60 * 1000;
constexpr int kKeepaliveTimeoutMs = 20 * 1000;

// Readiness turns NOT_SERVING when less than this part of the memory budget is left for new
// work once everything evictable is evicted.
constexpr int64_t kReadyMemoryFraction = 8;

int SaturatedMilliseconds(absl::Duration duration) {
  return static_cast<int>(std::min<int64_t>(absl::ToInt64Milliseconds(duration), INT32_MAX));
}

AuthenticationConfig AuthenticationConfigOf(const ServerConfig& config) {
  return {.tokens = config.auth_tokens,
          .client_certificates = !config.tls.client_ca.empty(),
          .admin_principals = config.admin_principals};
}

SchedulerConfig SchedulerConfigOf(const ServerConfig& config) {
  SchedulerConfig scheduler;
  scheduler.workers = config.workers;
  scheduler.max_queued_jobs = config.max_queued_jobs;
  scheduler.retention.max_finished = config.retain_finished_jobs;
  scheduler.retention.max_age = config.retain_finished_time;
  return scheduler;
}

struct Stores {
  std::unique_ptr<JobStore> jobs;  // null: the scheduler's in-memory default
  std::unique_ptr<MeshStore> meshes;
};

// The stores --job_store names.
absl::StatusOr<Stores> OpenStores(const ServerConfig& config) {
  if (config.job_store == "memory") {
    return Stores{nullptr, std::make_unique<InMemoryMeshStore>(config.max_stored_meshes)};
  }
  PostgresJobStoreOptions options;
  options.uri = config.job_store;
  options.retention = {.max_finished = config.retain_finished_jobs,
                       .max_age = config.retain_finished_time};
  options.lease = config.job_lease;
  options.operation_timeout = config.job_store_timeout;
  // Workers record events, gRPC threads look jobs up, plus the lease thread and notifications.
  options.connections = config.workers + 6;
  absl::StatusOr<std::unique_ptr<PostgresJobStore>> store = PostgresJobStore::Open(options);
  if (!store.ok()) return store.status();
  auto meshes = std::make_unique<PostgresMeshStore>((*store)->connections(),
                                                    config.max_stored_meshes, config.max_arcs);
  return Stores{*std::move(store), std::move(meshes)};
}

}  // namespace

QuantizerServer::QuantizerServer(const ServerConfig& config, std::unique_ptr<JobStore> jobs,
                                 std::unique_ptr<MeshStore> meshes)
    : config_(config),
      budget_(config.max_memory_bytes),
      meshes_(std::move(meshes)),
      authenticator_(AuthenticationConfigOf(config)),
      scheduler_(SchedulerConfigOf(config), metrics_, &budget_, std::move(jobs)),
      memory_(budget_, scheduler_, *meshes_, metrics_),
      service_(
          ServiceParts{
              .scheduler = scheduler_, .meshes = *meshes_, .metrics = metrics_, .memory = memory_},
          JobLimits{.max_arcs = config.max_arcs, .max_job_time = config.max_job_time},
          AdmissionConfig{.threads = config.admission_threads,
                          .max_waiting = config.max_waiting_admissions}),
      grpc_service_(service_, authenticator_, config.max_upload_bytes, config.upload_idle) {
  scheduler_.EnableClaiming(
      [this](const JobClaims::Claim& claim) { return service_.Readmit(claim); });
}

bool QuantizerServer::Ready() const {
  return scheduler_.accepting() && scheduler_.store_reachable() && !scheduler_.queue_full() &&
         !service_.admissions_full() && !service_.store_calls_full() &&
         budget_.pinned() <= budget_.limit() - budget_.limit() / kReadyMemoryFraction;
}

absl::StatusOr<std::unique_ptr<QuantizerServer>> QuantizerServer::Start(
    const ServerConfig& config) {
  if (absl::Status valid = ValidateServerConfig(config); !valid.ok()) return valid;
  absl::StatusOr<std::shared_ptr<grpc::ServerCredentials>> credentials =
      MakeServerCredentials(config.tls);
  if (!credentials.ok()) return credentials.status();
  // Read and checked before anything starts, like gRPC's, so a bad file stops the server at once.
  std::optional<http::HttpTlsMaterial> http_tls;
  if (const TlsFiles files = HttpTlsFiles(config); files.enabled()) {
    absl::StatusOr<http::HttpTlsMaterial> material =
        http::LoadHttpTlsMaterial(files.cert, files.key);
    if (!material.ok()) return material.status();
    http_tls = *std::move(material);
  }

  absl::StatusOr<Stores> stores = OpenStores(config);
  if (!stores.ok()) return stores.status();
  std::unique_ptr<QuantizerServer> server(
      new QuantizerServer(config, std::move(stores->jobs), std::move(stores->meshes)));
  grpc::EnableDefaultHealthCheckService(true);
  grpc::reflection::InitProtoReflectionServerBuilderPlugin();
  grpc::ServerBuilder builder;
  builder.AddListeningPort(config.listen_address, *credentials, &server->port_);
  // No SO_REUSEPORT (gRPC's default): a second server on a running one's address would share its
  // connections, and their jobs, each in its own memory, would be NOT_FOUND half of the time.
  builder.AddChannelArgument(GRPC_ARG_ALLOW_REUSEPORT, 0);
  builder.RegisterService(&server->grpc_service_);
  builder.SetMaxReceiveMessageSize(config.max_message_bytes);
  builder.AddChannelArgument(GRPC_ARG_KEEPALIVE_TIME_MS, kKeepaliveTimeMs);
  builder.AddChannelArgument(GRPC_ARG_KEEPALIVE_TIMEOUT_MS, kKeepaliveTimeoutMs);
  if (config.max_connection_age > absl::ZeroDuration()) {
    // Clients reconnect (and re-resolve a dns:/// target) when a connection reaches this age,
    // so new replicas get traffic; the grace lets calls in progress, the longest being a stream
    // of a job at its time limit, finish first.
    builder.AddChannelArgument(GRPC_ARG_MAX_CONNECTION_AGE_MS,
                               SaturatedMilliseconds(config.max_connection_age));
    builder.AddChannelArgument(GRPC_ARG_MAX_CONNECTION_AGE_GRACE_MS,
                               SaturatedMilliseconds(config.max_job_time + absl::Minutes(1)));
  }
  server->server_ = builder.BuildAndStart();
  if (server->server_ == nullptr || server->port_ == 0) {
    server->server_.reset();
    server->shut_down_ = true;  // nothing is listening: the destructor only stops the workers
    return absl::UnavailableError(absl::StrCat("cannot listen on ", config.listen_address));
  }
  if (!config.http_listen_address.empty()) {
    QuantizerServer* const owner = server.get();
    http::HttpParts parts{.service = owner->service_,
                          .authenticator = owner->authenticator_,
                          .memory = owner->memory_,
                          .metrics = owner->metrics_,
                          .live = [owner] { return owner->scheduler_.accepting(); },
                          .ready = [owner] { return owner->Ready(); }};
    http::HttpLimits limits;
    limits.max_body_bytes = config.max_message_bytes;
    limits.max_event_streams = config.http_max_event_streams;
    limits.allowed_hosts = config.http_allowed_hosts;
    absl::StatusOr<std::unique_ptr<http::HttpServer>> http = http::HttpServer::Start(
        config.http_listen_address, std::move(parts), std::move(limits), std::move(http_tls));
    if (!http.ok()) {
      server->Shutdown();
      return http.status();
    }
    server->http_ = *std::move(http);
  }
  grpc::HealthCheckServiceInterface* health = server->server_->GetHealthCheckService();
  health->SetServingStatus(v1::Quantizer::service_full_name(), true);
  QuantizerServer* const self = server.get();
  server->readiness_ = std::make_unique<ReadinessMonitor>(health, [self] { return self->Ready(); });
  spdlog::info(
      "event=server_start listen={} port={} http_port={} http_tls={} workers={} max_queued_jobs={} "
      "max_arcs={} "
      "max_message_bytes={} max_memory_bytes={} admission_threads={} max_job_seconds={} tls={} "
      "client_certificates={} token_principals={} admin_principals={} job_store={}",
      config.listen_address, server->port_, server->http_port(),
      server->http_ != nullptr && server->http_->tls(), config.workers, config.max_queued_jobs,
      config.max_arcs, config.max_message_bytes, config.max_memory_bytes, config.admission_threads,
      absl::ToDoubleSeconds(config.max_job_time), config.tls.enabled(),
      !config.tls.client_ca.empty(), config.auth_tokens.size(), config.admin_principals.size(),
      config.job_store == "memory" ? "memory" : "postgresql");
  return server;
}

QuantizerServer::~QuantizerServer() { Shutdown(); }

void QuantizerServer::Shutdown() {
  if (shut_down_) return;
  shut_down_ = true;
  const absl::Time begin = absl::Now();
  const absl::Time deadline = begin + config_.shutdown_grace;
  const absl::Duration flush_time = std::min(config_.shutdown_grace / 4, kMaxFlushTime);
  spdlog::info("event=shutdown_begin grace_seconds={}",
               absl::ToDoubleSeconds(config_.shutdown_grace));

  readiness_.reset();  // before the health service stops taking statuses
  server_->GetHealthCheckService()->Shutdown();
  scheduler_.StopAccepting();
  bool idle = scheduler_.WaitUntilIdle(deadline - flush_time);
  if (!idle) {
    spdlog::warn("event=shutdown_interrupt reason=\"grace period running out\"");
    scheduler_.InterruptRunning();
    idle = scheduler_.WaitUntilIdle(deadline - flush_time / 2);
  }
  // What the jobs reported reaches a shared store before the process goes (what does not, by
  // the deadline, is run again by another replica once its lease expires).
  const bool stored = scheduler_.FlushStore(deadline - flush_time / 2);
  // The jobs have ended: the HTTP event streams have their terminal events, which they write
  // before they look at the stop (within about a second).
  if (http_ != nullptr) http_->Stop();
  // Waits for the streams to deliver their terminal events, and cancels what is left at the
  // deadline.
  server_->Shutdown(absl::ToChronoTime(deadline));
  server_->Wait();
  spdlog::info("event=shutdown_end seconds={:.3f} jobs_idle={} jobs_stored={}",
               absl::ToDoubleSeconds(absl::Now() - begin), idle, stored);
}

}  // namespace ispq::server
