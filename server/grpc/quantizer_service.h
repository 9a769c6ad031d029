// SPDX-License-Identifier: Apache-2.0
// The ispq.v1.Quantizer service on gRPC's callback API: each method authenticates its caller
// (server/auth/authenticator.h), takes its request within the memory budget (server/grpc/request_intake.h),
// turns it into calls on the scheduler and the mesh store, and answers. No method blocks a gRPC
// thread on a solve or on a database: with stores in this process, lookups are answered on
// gRPC's thread; with a shared store (PostgreSQL), whose answers take a round trip or, when the
// database hangs, up to its operation timeout, lookups and small admissions run on a small pool
// of store-call threads (an AdmissionPool, bounded; full: UNAVAILABLE at once), so that a hung
// database can never take the threads that health checks need. Requests that carry a large mesh
// (Quantize, SubmitJob, CreateMesh) are parsed and validated on the admission pool
// (server/admission/admission_pool.h), and the two streaming methods hand the call to a JobEventStream
// that the job wakes up.
//
// Jobs and stored meshes are visible only to the principal that created them and to admins;
// others get NOT_FOUND, as for names that never existed. SubmitJob honours request_id
// (server/admission/request_ids.h).
//
// Methods are registered raw (see server/grpc/raw_proto_call.h) so that a request that does not
// parse is INVALID_ARGUMENT. The operations behind the methods (Submit, Watch, GetJob...) are
// public and transport-neutral, answering with absl::Status: the HTTP side (server/http/) calls
// them too, so both transports share semantics, limits and errors. Errors cross into gRPC in the
// gRPC methods here, into HTTP in server/http/http_status.h.
#ifndef ISPQ_SERVER_QUANTIZER_SERVICE_H_
#define ISPQ_SERVER_QUANTIZER_SERVICE_H_

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "absl/status/statusor.h"
#include "absl/time/time.h"
#include "grpcpp/support/byte_buffer.h"
#include "ispq/v1/service.grpc.pb.h"
#include "server/admission/admission_pool.h"
#include "server/admission/job_admission.h"
#include "server/admission/memory_admission.h"
#include "server/admission/request_ids.h"
#include "server/auth/authenticator.h"
#include "server/auth/principal.h"
#include "server/grpc/job_event_stream.h"
#include "server/grpc/job_submission.h"
#include "server/grpc/request_intake.h"
#include "server/grpc/unary_call.h"
#include "server/jobs/job_scheduler.h"
#include "server/metrics/server_metrics.h"
#include "server/model/job_spec.h"
#include "server/store/mesh_store.h"

namespace ispq::server {

// Every method of ispq.v1.Quantizer, raw.
using RawQuantizerService = v1::Quantizer::WithRawCallbackMethod_Quantize<
    v1::Quantizer::WithRawCallbackMethod_SubmitJob<v1::Quantizer::WithRawCallbackMethod_WatchJob<
        v1::Quantizer::WithRawCallbackMethod_GetJob<v1::Quantizer::WithRawCallbackMethod_ListJobs<
            v1::Quantizer::WithRawCallbackMethod_CancelJob<
                v1::Quantizer::WithRawCallbackMethod_CreateMesh<
                    v1::Quantizer::WithRawCallbackMethod_GetMesh<
                        v1::Quantizer::WithRawCallbackMethod_DeleteMesh<
                            v1::Quantizer::WithRawCallbackMethod_GetServerStats<
                                v1::Quantizer::Service>>>>>>>>>>;

// A job to stream to a watcher, from event `from_event` on.
struct WatchTarget {
  std::shared_ptr<Job> job;
  int64_t from_event = 0;
};

// What the service works with; everything must outlive the gRPC server that serves it.
struct ServiceParts {
  JobScheduler& scheduler;
  MeshStore& meshes;
  ServerMetrics& metrics;
  MemoryAdmission& memory;
  const Authenticator& authenticator;
};

struct AdmissionConfig {
  int threads = 1;
  int max_waiting = 64;  // requests waiting for an admission thread; beyond, RESOURCE_EXHAUSTED
};

class QuantizerService final : public RawQuantizerService {
 public:
  QuantizerService(ServiceParts parts, JobLimits limits, AdmissionConfig admission);
  // Runs the admissions still waiting (they find the scheduler closed) and joins the pool.
  ~QuantizerService() override = default;

  grpc::ServerWriteReactor<grpc::ByteBuffer>* Quantize(grpc::CallbackServerContext* context,
                                                       const grpc::ByteBuffer* request) override;
  grpc::ServerWriteReactor<grpc::ByteBuffer>* WatchJob(grpc::CallbackServerContext* context,
                                                       const grpc::ByteBuffer* request) override;
  grpc::ServerUnaryReactor* SubmitJob(grpc::CallbackServerContext* context,
                                      const grpc::ByteBuffer* request,
                                      grpc::ByteBuffer* response) override;
  grpc::ServerUnaryReactor* GetJob(grpc::CallbackServerContext* context,
                                   const grpc::ByteBuffer* request,
                                   grpc::ByteBuffer* response) override;
  grpc::ServerUnaryReactor* ListJobs(grpc::CallbackServerContext* context,
                                     const grpc::ByteBuffer* request,
                                     grpc::ByteBuffer* response) override;
  grpc::ServerUnaryReactor* CancelJob(grpc::CallbackServerContext* context,
                                      const grpc::ByteBuffer* request,
                                      grpc::ByteBuffer* response) override;
  grpc::ServerUnaryReactor* CreateMesh(grpc::CallbackServerContext* context,
                                       const grpc::ByteBuffer* request,
                                       grpc::ByteBuffer* response) override;
  grpc::ServerUnaryReactor* GetMesh(grpc::CallbackServerContext* context,
                                    const grpc::ByteBuffer* request,
                                    grpc::ByteBuffer* response) override;
  grpc::ServerUnaryReactor* DeleteMesh(grpc::CallbackServerContext* context,
                                       const grpc::ByteBuffer* request,
                                       grpc::ByteBuffer* response) override;
  grpc::ServerUnaryReactor* GetServerStats(grpc::CallbackServerContext* context,
                                           const grpc::ByteBuffer* request,
                                           grpc::ByteBuffer* response) override;

  // Re-admits a job claimed from a shared store (server/jobs/job_claimer.h): its stored request, as
  // its owner's, who was authorized when the job was submitted.
  absl::StatusOr<JobSpec> Readmit(const JobClaims::Claim& claim);

  // ---- The same operations for other transports (the HTTP side, server/http/) ----
  // They take an authenticated principal and answer as the gRPC methods do.

  // SubmitJob: validates and queues the request, answering through `submission.answer`.
  void Submit(JobSubmission submission);
  // The job and first event a WatchJob request names.
  absl::StatusOr<WatchTarget> Watch(const v1::WatchJobRequest& request, const Principal& principal);
  absl::StatusOr<v1::Job> GetJob(const v1::GetJobRequest& request, const Principal& principal);
  absl::StatusOr<v1::ListJobsResponse> ListJobs(const v1::ListJobsRequest& request,
                                                const Principal& principal);
  absl::StatusOr<v1::Job> CancelJob(const v1::CancelJobRequest& request,
                                    const Principal& principal);
  // GetServerStats' answer.
  v1::ServerStats Stats() const;

  // Requests received and not yet admitted or refused, and whether more would be refused.
  int admissions_in_progress() const { return admission_pool_.in_progress(); }
  bool admissions_full() const { return admission_pool_.full(); }
  // Whether calls that need the shared store would be refused (never without one).
  bool store_calls_full() const { return store_calls_ != nullptr && store_calls_->full(); }

 private:
  // ---- Requests that carry a mesh, run by Dispatch ----
  void AdmitQuantize(grpc::CallbackServerContext& context, JobEventStream& stream,
                     const Principal& principal, RawRequest& raw);
  absl::StatusOr<std::shared_ptr<Job>> QuantizeJob(grpc::CallbackServerContext& context,
                                                   const Principal& principal, RawRequest& raw);
  void AdmitSubmission(const std::shared_ptr<JobSubmission>& submission);
  // The submission's outcome; none when another call with the same request id will answer it.
  std::optional<JobSubmission::Outcome> DecideSubmission(
      const std::shared_ptr<JobSubmission>& submission);
  absl::StatusOr<v1::Mesh> AdmitCreateMesh(UnaryCall& call, const Principal& principal,
                                           RawRequest& raw);
  // The mesh of a CreateMesh request, validated, with memory reserved in the store's account.
  absl::StatusOr<AdmittedMesh> StoreableMesh(const v1::TMesh& proto, int64_t request_bytes);
  // Runs `admit` at once for a small request (on a store-call thread with a shared store), else
  // on the admission pool; false if the pool it needs is full.
  bool Dispatch(int64_t request_bytes, AdmissionPool::Task admit);
  // Why Dispatch refused a request of `request_bytes`.
  absl::Status DispatchRefused(int64_t request_bytes) const;
  absl::Status AdmissionPoolFull() const;
  // Runs `task` at once, or on a store-call thread with a shared store; false if they are all
  // busy and enough wait.
  bool OffGrpcThread(AdmissionPool::Task task);
  absl::Status StoreCallsFull() const;

  // Validates the request into a job and queues it. `fingerprint`: the request's without its
  // request_id, when it has one (a shared store compares it across replicas).
  absl::StatusOr<std::shared_ptr<Job>> AdmitJob(const std::string& peer, const Principal& principal,
                                                const v1::QuantizeRequest& request,
                                                int64_t request_bytes, bool bound_to_call,
                                                std::string fingerprint = "");
  // What every unary method does first: the caller's principal and the request's bytes (at most
  // `max_bytes`, counted in the memory budget). Nothing if either fails; `call` has then failed.
  struct AcceptedRequest {
    Principal principal;
    RawRequest raw;
  };
  std::optional<AcceptedRequest> Accept(UnaryCall& call, const grpc::ByteBuffer* request,
                                        int64_t max_bytes);
  // Answers a SubmitJob with its job or error.
  static void AnswerJob(UnaryCall& call, const absl::StatusOr<std::shared_ptr<Job>>& job);

  // A lookup: authenticate, take and parse `Request` on gRPC's thread, answer with
  // `handler(request, principal)` (-> StatusOr<Response>) there or on a store-call thread.
  template <typename Request, typename Handler>
  grpc::ServerUnaryReactor* Lookup(grpc::CallbackServerContext* context,
                                   const grpc::ByteBuffer* request, grpc::ByteBuffer* response,
                                   Handler&& handler);

  // The caller and the WatchJob request of a call.
  struct WatchCall {
    Principal principal;
    v1::WatchJobRequest request;
  };
  absl::StatusOr<WatchCall> AcceptWatch(grpc::CallbackServerContext& context,
                                        const grpc::ByteBuffer* request);
  // The job `name` if `principal` may see it, else NOT_FOUND (as if it did not exist).
  absl::StatusOr<std::shared_ptr<Job>> FindJob(const std::string& name, const Principal& principal);

  JobScheduler& scheduler_;
  MeshStore& meshes_;
  ServerMetrics& metrics_;
  MemoryAdmission& memory_;
  const Authenticator& authenticator_;
  const JobLimits limits_;
  const absl::Time start_time_;
  RequestIds request_ids_;
  // With a shared store only; destroyed (drained and joined) before everything they use.
  std::unique_ptr<AdmissionPool> store_calls_;
  AdmissionPool admission_pool_;  // last: destroyed (drained and joined) first
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_QUANTIZER_SERVICE_H_
