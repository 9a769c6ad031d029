// The ispq.v1.Quantizer service on gRPC's callback API: each method authenticates its caller
// (server/authenticator.h), takes its request within the memory budget (server/request_intake.h),
// turns it into calls on the scheduler and the mesh store, and answers. No method blocks a gRPC
// thread on a solve: lookups are answered on gRPC's thread, requests that carry a mesh (Quantize,
// SubmitJob, CreateMesh) are parsed and validated on the admission pool (server/admission_pool.h)
// unless they are small, and the two streaming methods hand the call to a JobEventStream that the
// job wakes up.
//
// Jobs and stored meshes are visible only to the principal that created them and to admins;
// others get NOT_FOUND, as for names that never existed. SubmitJob honours request_id
// (server/request_ids.h).
//
// Methods are registered raw (see server/raw_proto_call.h) so that a request that does not
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
#include "server/admission_pool.h"
#include "server/authenticator.h"
#include "server/job_event_stream.h"
#include "server/job_scheduler.h"
#include "server/job_spec.h"
#include "server/job_submission.h"
#include "server/memory_admission.h"
#include "server/mesh_store.h"
#include "server/principal.h"
#include "server/request_ids.h"
#include "server/request_intake.h"
#include "server/server_metrics.h"
#include "server/unary_call.h"

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

  // Re-admits a job claimed from a shared store (server/job_claimer.h): its stored request, as
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

 private:
  // ---- Requests that carry a mesh, run by Dispatch ----
  void AdmitQuantize(grpc::CallbackServerContext& context, JobEventStream& stream,
                     const Principal& principal, RawRequest& raw);
  absl::StatusOr<std::shared_ptr<Job>> QuantizeJob(grpc::CallbackServerContext& context,
                                                   const Principal& principal, RawRequest& raw);
  void AdmitSubmission(const std::shared_ptr<JobSubmission>& submission);
  void AdmitCreateMesh(UnaryCall& call, const Principal& principal, RawRequest& raw);
  // The mesh of a CreateMesh request, validated, with memory reserved in the store's account.
  absl::StatusOr<AdmittedMesh> StoreableMesh(const v1::TMesh& proto, int64_t request_bytes);
  // Runs `admit` at once for a small request, else on the admission pool; false if it is full.
  bool Dispatch(int64_t request_bytes, AdmissionPool::Task admit);
  absl::Status AdmissionPoolFull() const;

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

  // A lookup on gRPC's thread: authenticate, take and parse `Request`, answer with
  // `handler(request, principal)` (-> StatusOr<Response>).
  template <typename Request, typename Handler>
  grpc::ServerUnaryReactor* Lookup(grpc::CallbackServerContext* context,
                                   const grpc::ByteBuffer* request, grpc::ByteBuffer* response,
                                   Handler&& handler);

  // The job a WatchJob request names, and the event to start from.
  absl::StatusOr<WatchTarget> WatchedJob(grpc::CallbackServerContext& context,
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
  AdmissionPool admission_pool_;  // last: destroyed (drained and joined) first
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_QUANTIZER_SERVICE_H_
