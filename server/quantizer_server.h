// SPDX-License-Identifier: Apache-2.0
// ispq-server: the quantization service of proto/ispq/v1/service.proto, with standard health
// checking (grpc.health.v1: liveness, and readiness as service "readiness") and server
// reflection, as one object that owns all its parts.
//
// Threading model
//   * gRPC's callback API. RPC handlers run on gRPC's own threads and never block: lookups are
//     answered there; requests that carry a mesh (Quantize, SubmitJob, CreateMesh) are parsed
//     and validated there only when small, else on a small admission pool (--admission_threads,
//     server/admission/admission_pool.h), so that a burst of large requests cannot occupy gRPC's
//     threads and stall health checks. The streaming methods (Quantize, WatchJob) return a reactor
//     (JobEventStream) that writes one event at a time and is woken by the job when it has a new
//     event and by gRPC when a write completes. A thousand watchers cost a thousand small
//     objects, not a thousand threads.
//   * A fixed pool of worker threads (--workers, default one per hardware thread). Each worker
//     takes one job at a time from a bounded FIFO queue (--max_queued_jobs) and runs the core
//     quantizer on it single-threaded; admission past a full queue is RESOURCE_EXHAUSTED with a
//     retry hint. The solver reports progress on the worker's thread into the job's event log
//     (rate-limited and compacted), which notifies the job's streams.
//   * Cancellation is cooperative: CancelJob, the end of a Quantize call (client cancel,
//     disconnect, deadline) and shutdown set the job's SolveInterrupter, which the solver checks
//     between LP solves; it then returns the best valid quantization found so far, if any.
//   * Readiness is polled by a thread of its own (server/readiness_monitor.h).
//   * Shared state: each job guards itself with one mutex; the job store, queue, mesh store,
//     request ids, admission pool, memory budget and histograms each have their own. Locks are
//     never held while calling into gRPC or while notifying watchers; the nesting is
//     request ids -> store -> job, store/stream -> job, and anything -> memory budget (which
//     calls nothing).
//
// Memory: everything held for clients is accounted in one budget (--max_memory_bytes,
// server/memory/memory_budget.h): requests while they are admitted, queued and running jobs' meshes
// and solver memory, stored meshes, retained results and responses in flight. Admission refuses
// what does not fit after evicting retained results and stored meshes
// (server/admission/memory_admission.h).
//
// Transports: the service's operations are transport-neutral (server/service/job_service.h);
// the gRPC service (server/grpc/quantizer_service.h) is an adapter over them, and so is the
// HTTP side (--http_listen, server/http/http_server.h): a second listener on threads of its own
// that calls the same service operations, so both transports share jobs, principals, limits
// and the memory budget; its /healthz and /readyz report what the gRPC health service does.
//
// Ownership: QuantizerServer owns the metrics, the memory budget, the mesh store, the
// authenticator, the scheduler (job store, queue, workers), the service (with the admission
// pool and the request ids), its gRPC adapter, the grpc::Server, the readiness monitor and the
// HTTP server; jobs are shared between the scheduler and the streams watching them. Members are
// destroyed in reverse order: the HTTP server (stopped in Shutdown already), the readiness
// monitor, the gRPC server (no more calls), the gRPC adapter, the service (drains the admission
// pool), then the scheduler (joins the workers), and the budget last, after everything that holds
// reservations on it.
//
// Graceful shutdown (SIGTERM/SIGINT in server_main.cc, or Shutdown()): health turns
// NOT_SERVING, new jobs are refused with UNAVAILABLE and queued ones end with UNAVAILABLE (they
// never started, so clients can resubmit elsewhere); running jobs may finish until a quarter of
// the grace period (at most 5 s) is left, then they are interrupted and end with their best
// result; the remaining time lets the streams deliver the terminal events before gRPC cancels
// whatever is left. Job queries keep working until the end.
#ifndef ISPQ_SERVER_QUANTIZER_SERVER_H_
#define ISPQ_SERVER_QUANTIZER_SERVER_H_

#include <memory>

#include "absl/status/statusor.h"
#include "grpcpp/server.h"
#include "server/admission/memory_admission.h"
#include "server/auth/authenticator.h"
#include "server/grpc/quantizer_service.h"
#include "server/http/http_server.h"
#include "server/jobs/job_scheduler.h"
#include "server/memory/memory_budget.h"
#include "server/metrics/server_metrics.h"
#include "server/readiness_monitor.h"
#include "server/server_config.h"
#include "server/service/job_service.h"
#include "server/store/job_store.h"
#include "server/store/mesh_store.h"

namespace ispq::server {

class QuantizerServer {
 public:
  // Validates the configuration, starts the workers and listens. INVALID_ARGUMENT for a bad
  // configuration or unusable TLS files, UNAVAILABLE if the address cannot be bound.
  static absl::StatusOr<std::unique_ptr<QuantizerServer>> Start(const ServerConfig& config);

  // Shuts down gracefully if Shutdown was not called.
  ~QuantizerServer();
  QuantizerServer(const QuantizerServer&) = delete;
  QuantizerServer& operator=(const QuantizerServer&) = delete;

  // The bound port (useful with port 0 in --listen).
  int port() const { return port_; }
  // The HTTP side's bound port, 0 without --http_listen.
  int http_port() const { return http_ == nullptr ? 0 : http_->port(); }

  // Graceful shutdown within the configured grace period (see the file comment). Idempotent.
  void Shutdown();

 private:
  QuantizerServer(const ServerConfig& config, std::unique_ptr<JobStore> jobs,
                  std::unique_ptr<MeshStore> meshes);

  // Whether a new job would be accepted now (server/readiness_monitor.h).
  bool Ready() const;

  const ServerConfig config_;
  ServerMetrics metrics_;
  MemoryBudget budget_;
  std::unique_ptr<MeshStore> meshes_;
  Authenticator authenticator_;
  JobScheduler scheduler_;
  MemoryAdmission memory_;
  JobService service_;
  QuantizerService grpc_service_;  // the gRPC adapter over service_
  std::unique_ptr<grpc::Server> server_;
  std::unique_ptr<ReadinessMonitor> readiness_;
  std::unique_ptr<http::HttpServer> http_;  // null without --http_listen
  int port_ = 0;
  bool shut_down_ = false;
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_QUANTIZER_SERVER_H_
