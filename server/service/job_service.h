// SPDX-License-Identifier: Apache-2.0
// The quantization service, whichever transport brings its calls (gRPC's, server/grpc/; the HTTP
// side's, server/http/): its operations take an authenticated principal and a request taken from
// the call (server/admission/raw_request.h), and answer with absl::Status, which each transport
// turns into its own errors (server/grpc/grpc_status.h, server/http/http_status.h). Both
// transports call the same operations, so they share semantics, limits and errors.
//
// Requests that carry a large mesh (Quantize, SubmitJob, CreateMesh) are parsed and validated on
// an admission pool (server/admission/admission_pool.h), small ones at once. Nothing blocks a
// transport's thread on a solve or on a database: with stores in this process, lookups are
// answered on the caller's thread; with a shared store (PostgreSQL), whose answers take a round
// trip or, when the database hangs, up to its operation timeout, small admissions and the
// transports' lookups (OffTransportThread) run on a small pool of store-call threads (bounded;
// full: UNAVAILABLE at once), so that a hung database can never take the threads that health
// checks need.
//
// Jobs and stored meshes are visible only to the principal that created them and to admins;
// others get NOT_FOUND, as for names that never existed. SubmitJob honours request_id
// (server/admission/request_ids.h).
#ifndef ISPQ_SERVER_SERVICE_JOB_SERVICE_H_
#define ISPQ_SERVER_SERVICE_JOB_SERVICE_H_

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "absl/time/time.h"
#include "ispq/v1/service.pb.h"
#include "server/admission/admission_pool.h"
#include "server/admission/job_admission.h"
#include "server/admission/memory_admission.h"
#include "server/admission/raw_request.h"
#include "server/admission/request_ids.h"
#include "server/auth/principal.h"
#include "server/jobs/job_scheduler.h"
#include "server/metrics/server_metrics.h"
#include "server/model/job_spec.h"
#include "server/service/job_submission.h"
#include "server/store/job_claims.h"
#include "server/store/mesh_store.h"

namespace ispq::server {

// A job to stream to a watcher, from event `from_event` on.
struct WatchTarget {
  std::shared_ptr<Job> job;
  int64_t from_event = 0;
};

// A CreateMesh request as the service takes it from a transport: as a JobSubmission, with the
// stored mesh (or the error) as the answer.
struct MeshCreation {
  Principal principal;
  RawRequest raw;  // a serialized ispq.v1.CreateMeshRequest, accounted in the memory budget
  // > 0: `raw` is exactly this many bytes of the request's field `mesh` (its tag and length) and
  // the mesh's bytes (an upload, server/grpc/mesh_upload.h), which are then decoded one element
  // at a time instead of parsed as one message.
  int64_t mesh_offset = 0;
  // Whether the caller has gone away; admission then stops before parsing. Empty: never.
  std::function<bool()> abandoned;
  // Called exactly once, on whichever thread decided it (the caller's own or an admission one).
  std::function<void(const absl::StatusOr<v1::Mesh>&)> answer;
};

// What the service works with; everything must outlive it.
struct ServiceParts {
  JobScheduler& scheduler;
  MeshStore& meshes;
  ServerMetrics& metrics;
  MemoryAdmission& memory;
};

struct AdmissionConfig {
  int threads = 1;
  int max_waiting = 64;  // requests waiting for an admission thread; beyond, RESOURCE_EXHAUSTED
};

class JobService {
 public:
  JobService(ServiceParts parts, JobLimits limits, AdmissionConfig admission);
  // Runs the admissions and store calls still waiting (they find the scheduler closed) and
  // joins their threads.
  ~JobService() = default;
  JobService(const JobService&) = delete;
  JobService& operator=(const JobService&) = delete;

  // ---- Requests that carry a mesh: admitted at once or on the admission pool ----

  // Quantize: validates and queues the request as a job bound to its call (it runs here or not
  // at all, and has no request id), answering through `submission.answer`; the transport
  // streams the job's events and cancels it when the call ends.
  void Quantize(JobSubmission submission);
  // SubmitJob: validates and queues the request, answering through `submission.answer`.
  void Submit(JobSubmission submission);
  // CreateMesh: validates and stores the mesh, answering through `creation.answer`.
  void CreateMesh(MeshCreation creation);

  // Re-admits a job claimed from a shared store (server/jobs/job_claimer.h): its stored request, as
  // its owner's, who was authorized when the job was submitted.
  absl::StatusOr<JobSpec> Readmit(const JobClaims::Claim& claim);

  // ---- Lookups: answered on the caller's thread (see OffTransportThread) ----

  // The job and first event a WatchJob request names.
  absl::StatusOr<WatchTarget> Watch(const v1::WatchJobRequest& request, const Principal& principal);
  absl::StatusOr<v1::Job> GetJob(const v1::GetJobRequest& request, const Principal& principal);
  absl::StatusOr<v1::ListJobsResponse> ListJobs(const v1::ListJobsRequest& request,
                                                const Principal& principal);
  absl::StatusOr<v1::Job> CancelJob(const v1::CancelJobRequest& request,
                                    const Principal& principal);
  absl::StatusOr<v1::Mesh> GetMesh(const v1::GetMeshRequest& request, const Principal& principal);
  absl::StatusOr<v1::DeleteMeshResponse> DeleteMesh(const v1::DeleteMeshRequest& request,
                                                    const Principal& principal);
  // GetServerStats' answer.
  v1::ServerStats Stats() const;

  // Runs `task` at once, or with a shared store on a store-call thread, for a transport whose
  // threads must not wait on the database (gRPC's); false if those are all busy and enough
  // calls wait (then StoreCallsFull() is the answer).
  bool OffTransportThread(AdmissionPool::Task task);
  absl::Status StoreCallsFull() const;

  // Requests received and not yet admitted or refused, and whether more would be refused.
  int admissions_in_progress() const { return admission_pool_.in_progress(); }
  bool admissions_full() const { return admission_pool_.full(); }
  // Whether calls that need the shared store would be refused (never without one).
  bool store_calls_full() const { return store_calls_ != nullptr && store_calls_->full(); }

  // What the transports take requests into and stream jobs from.
  MemoryAdmission& memory() { return memory_; }
  JobScheduler& scheduler() { return scheduler_; }

 private:
  JobSubmission::Outcome QuantizeJob(JobSubmission& submission);
  void AdmitSubmission(const std::shared_ptr<JobSubmission>& submission);
  // The submission's outcome; none when another call with the same request id will answer it.
  std::optional<JobSubmission::Outcome> DecideSubmission(
      const std::shared_ptr<JobSubmission>& submission);
  absl::StatusOr<v1::Mesh> AdmitCreateMesh(MeshCreation& creation);
  absl::StatusOr<v1::Mesh> AdmitUploadedMesh(MeshCreation& creation);
  // Stores an admitted mesh (or counts why it was refused) and answers with its resource.
  absl::StatusOr<v1::Mesh> StoreMesh(absl::StatusOr<AdmittedMesh> mesh,
                                     const MeshBytesSource& bytes, const Principal& principal);
  // The mesh of a CreateMesh request, validated, with memory reserved in the store's account.
  absl::StatusOr<AdmittedMesh> StoreableMesh(const v1::TMesh& proto, int64_t request_bytes);
  // Runs `admit` at once for a small request (on a store-call thread with a shared store), else
  // on the admission pool; false if the pool it needs is full.
  bool Dispatch(int64_t request_bytes, AdmissionPool::Task admit);
  // Why Dispatch refused a request of `request_bytes`.
  absl::Status DispatchRefused(int64_t request_bytes) const;
  absl::Status AdmissionPoolFull() const;

  // Validates the request into a job and queues it. `fingerprint`: the request's without its
  // request_id, when it has one (a shared store compares it across replicas).
  absl::StatusOr<std::shared_ptr<Job>> AdmitJob(const std::string& peer, const Principal& principal,
                                                const v1::QuantizeRequest& request,
                                                int64_t request_bytes, bool bound_to_call,
                                                std::string fingerprint = "");
  // The job `name` if `principal` may see it, else NOT_FOUND (as if it did not exist).
  absl::StatusOr<std::shared_ptr<Job>> FindJob(const std::string& name, const Principal& principal);

  JobScheduler& scheduler_;
  MeshStore& meshes_;
  ServerMetrics& metrics_;
  MemoryAdmission& memory_;
  const JobLimits limits_;
  const absl::Time start_time_;
  RequestIds request_ids_;
  // With a shared store only; destroyed (drained and joined) before everything they use.
  std::unique_ptr<AdmissionPool> store_calls_;
  AdmissionPool admission_pool_;  // last: destroyed (drained and joined) first
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_SERVICE_JOB_SERVICE_H_
