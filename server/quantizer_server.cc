#include "server/quantizer_server.h"

#include <algorithm>
#include <utility>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "absl/time/clock.h"
#include "grpcpp/ext/proto_server_reflection_plugin.h"
#include "grpcpp/health_check_service_interface.h"
#include "grpcpp/server_builder.h"
#include "server/server_credentials.h"
#include "spdlog/spdlog.h"

namespace ispq::server {
namespace {

// Part of the grace period kept for streams to deliver the terminal events of interrupted jobs.
constexpr absl::Duration kMaxFlushTime = absl::Seconds(5);

// HTTP/2 keepalive: a client that vanished without closing its connection is noticed within
// about this long, so a Quantize job bound to it gets cancelled instead of running on.
constexpr int kKeepaliveTimeMs = 60 * 1000;
constexpr int kKeepaliveTimeoutMs = 20 * 1000;

SchedulerConfig SchedulerConfigOf(const ServerConfig& config) {
  SchedulerConfig scheduler;
  scheduler.workers = config.workers;
  scheduler.max_queued_jobs = config.max_queued_jobs;
  scheduler.retention.max_finished = config.retain_finished_jobs;
  scheduler.retention.max_age = config.retain_finished_time;
  return scheduler;
}

}  // namespace

QuantizerServer::QuantizerServer(const ServerConfig& config)
    : config_(config),
      meshes_(config.max_stored_meshes),
      authenticator_(config.auth_token),
      scheduler_(SchedulerConfigOf(config), metrics_),
      service_(scheduler_, meshes_, metrics_, authenticator_,
               JobLimits{.max_arcs = config.max_arcs, .max_job_time = config.max_job_time}) {}

absl::StatusOr<std::unique_ptr<QuantizerServer>> QuantizerServer::Start(
    const ServerConfig& config) {
  if (absl::Status valid = ValidateServerConfig(config); !valid.ok()) return valid;
  absl::StatusOr<std::shared_ptr<grpc::ServerCredentials>> credentials =
      MakeServerCredentials(config.tls);
  if (!credentials.ok()) return credentials.status();

  std::unique_ptr<QuantizerServer> server(new QuantizerServer(config));
  grpc::EnableDefaultHealthCheckService(true);
  grpc::reflection::InitProtoReflectionServerBuilderPlugin();
  grpc::ServerBuilder builder;
  builder.AddListeningPort(config.listen_address, *credentials, &server->port_);
  builder.RegisterService(&server->service_);
  builder.SetMaxReceiveMessageSize(config.max_message_bytes);
  builder.AddChannelArgument(GRPC_ARG_KEEPALIVE_TIME_MS, kKeepaliveTimeMs);
  builder.AddChannelArgument(GRPC_ARG_KEEPALIVE_TIMEOUT_MS, kKeepaliveTimeoutMs);
  server->server_ = builder.BuildAndStart();
  if (server->server_ == nullptr || server->port_ == 0) {
    server->server_.reset();
    server->shut_down_ = true;  // nothing is listening: the destructor only stops the workers
    return absl::UnavailableError(absl::StrCat("cannot listen on ", config.listen_address));
  }
  server->server_->GetHealthCheckService()->SetServingStatus(v1::Quantizer::service_full_name(),
                                                             true);
  spdlog::info(
      "event=server_start listen={} port={} workers={} max_queued_jobs={} max_arcs={} "
      "max_message_bytes={} max_job_seconds={} tls={} client_certificates={} auth_token={}",
      config.listen_address, server->port_, config.workers, config.max_queued_jobs, config.max_arcs,
      config.max_message_bytes, absl::ToDoubleSeconds(config.max_job_time), config.tls.enabled(),
      !config.tls.client_ca.empty(), !config.auth_token.empty());
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

  server_->GetHealthCheckService()->Shutdown();
  scheduler_.StopAccepting();
  bool idle = scheduler_.WaitUntilIdle(deadline - flush_time);
  if (!idle) {
    spdlog::warn("event=shutdown_interrupt reason=\"grace period running out\"");
    scheduler_.InterruptRunning();
    idle = scheduler_.WaitUntilIdle(deadline - flush_time / 2);
  }
  // Waits for the streams to deliver their terminal events, and cancels what is left at the
  // deadline.
  server_->Shutdown(absl::ToChronoTime(deadline));
  server_->Wait();
  spdlog::info("event=shutdown_end seconds={:.3f} jobs_idle={}",
               absl::ToDoubleSeconds(absl::Now() - begin), idle);
}

}  // namespace ispq::server
