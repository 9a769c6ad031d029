// SPDX-License-Identifier: Apache-2.0
#include "server/service/job_service.h"

#include <utility>

#include "absl/strings/str_cat.h"
#include "absl/time/clock.h"
#include "google/protobuf/util/time_util.h"
#include "server/admission/request_fingerprint.h"
#include "server/jobs/retry_hint.h"
#include "server/logging/log_value.h"
#include "server/memory/memory_estimates.h"
#include "server/model/mesh_admission.h"
#include "server/model/resource_names.h"
#include "spdlog/spdlog.h"

namespace ispq::server {
namespace {

using google::protobuf::util::TimeUtil;

// Requests up to this size are admitted on the caller's thread: parsing and validating them
// takes about a millisecond, less than handing them to another thread would add.
constexpr int64_t kInlineAdmissionBytes = 256 << 10;
// A ListJobs page stops before its serialized size passes this (clients' default limit: 4 MiB).
constexpr int64_t kMaxListPageBytes = (4 << 20) - (64 << 10);
constexpr absl::Duration kAdmissionRetryHint = absl::Milliseconds(500);
// With a shared store: threads for calls that wait on the database, and how many calls may wait
// for them. A call waits at most the store's operation timeout, so a hung database fills the
// queue within seconds; later calls are refused at once rather than queued behind it.
constexpr int kStoreCallThreads = 4;
constexpr int kMaxWaitingStoreCalls = 256;

v1::Mesh MeshToProto(const StoredMesh& stored) {
  v1::Mesh proto;
  proto.set_name(ResourceName(kMeshCollection, stored.id));
  proto.set_display_name(stored.admitted.mesh->name());
  *proto.mutable_mesh_stats() = stored.admitted.stats;
  *proto.mutable_create_time() =
      TimeUtil::NanosecondsToTimestamp(absl::ToUnixNanos(stored.create_time));
  proto.set_owner(stored.owner);
  return proto;
}

absl::Status CancelledBeforeAdmission() {
  return absl::CancelledError("the call ended before its request was admitted");
}

}  // namespace

JobService::JobService(ServiceParts parts, JobLimits limits, AdmissionConfig admission)
    : scheduler_(parts.scheduler),
      meshes_(parts.meshes),
      metrics_(parts.metrics),
      memory_(parts.memory),
      limits_(limits),
      start_time_(absl::Now()),
      request_ids_(
          [&scheduler = parts.scheduler](const std::string& id) { return scheduler.Find(id); }),
      store_calls_(parts.scheduler.shared()
                       ? std::make_unique<AdmissionPool>(kStoreCallThreads, kMaxWaitingStoreCalls)
                       : nullptr),
      admission_pool_(admission.threads, admission.max_waiting) {}

// ---------------------------------------------------------------------------------------------
// Requests that carry a mesh

bool JobService::Dispatch(int64_t request_bytes, AdmissionPool::Task admit) {
  if (request_bytes <= kInlineAdmissionBytes) return OffTransportThread(std::move(admit));
  return admission_pool_.TrySchedule(std::move(admit));
}

bool JobService::OffTransportThread(AdmissionPool::Task task) {
  if (store_calls_ == nullptr) {
    std::move(task)();
    return true;
  }
  return store_calls_->TrySchedule(std::move(task));
}

absl::Status JobService::StoreCallsFull() const {
  return absl::UnavailableError(
      absl::StrCat("too many calls are waiting for the job store's database (",
                   kMaxWaitingStoreCalls, "): it answers slowly or not at all; retry later"));
}

absl::Status JobService::DispatchRefused(int64_t request_bytes) const {
  if (request_bytes <= kInlineAdmissionBytes) return StoreCallsFull();
  return AdmissionPoolFull();
}

absl::Status JobService::AdmissionPoolFull() const {
  metrics_.RecordRejectedQueueFull();
  return ResourceExhaustedWithRetryHint(
      absl::StrCat("too many large requests are waiting to be admitted (",
                   admission_pool_.max_waiting(), ")"),
      kAdmissionRetryHint);
}

absl::StatusOr<std::shared_ptr<Job>> JobService::AdmitJob(const std::string& peer,
                                                          const Principal& principal,
                                                          const v1::QuantizeRequest& request,
                                                          int64_t request_bytes, bool bound_to_call,
                                                          std::string fingerprint) {
  if (!scheduler_.accepting()) {
    return absl::UnavailableError("the server is shutting down and accepts no jobs");
  }
  const AdmissionContext admission{limits_, principal, meshes_, memory_};
  absl::StatusOr<JobSpec> spec = PrepareJobSpec(request, request_bytes, admission);
  if (!spec.ok()) {
    if (absl::IsInvalidArgument(spec.status())) metrics_.RecordRejectedInvalid();
    spdlog::debug("event=job_rejected peer={} code={} error={}", peer,
                  absl::StatusCodeToString(spec.status().code()),
                  QuotedLogValue(std::string(spec.status().message())));
    return spec.status();
  }
  spec->request_fingerprint = std::move(fingerprint);
  // A shared store keeps the request, so that any replica can run the job (not a call-bound
  // one: it runs here or not at all).
  const std::string stored =
      scheduler_.shared() && !bound_to_call ? request.SerializeAsString() : std::string();
  return scheduler_.Submit(*std::move(spec), bound_to_call, stored);
}

void JobService::Quantize(JobSubmission submission) {
  auto shared = std::make_shared<JobSubmission>(std::move(submission));
  const int64_t size = shared->raw.size;
  const bool dispatched = Dispatch(size, [this, shared] {
    // Decided first, answered after: the parsed request's reservation is gone by then.
    const JobSubmission::Outcome job = QuantizeJob(*shared);
    shared->answer(job);
  });
  if (!dispatched) {
    Discard(shared->raw);
    shared->answer(DispatchRefused(size));
  }
}

JobSubmission::Outcome JobService::QuantizeJob(JobSubmission& submission) {
  if (submission.abandoned && submission.abandoned()) return CancelledBeforeAdmission();
  absl::StatusOr<ParsedRequest<v1::QuantizeRequest>> parsed =
      ParseWithinBudget<v1::QuantizeRequest>(submission.raw, memory_);
  if (!parsed.ok()) {
    if (absl::IsInvalidArgument(parsed.status())) metrics_.RecordRejectedInvalid();
    return parsed.status();
  }
  if (!parsed->message.request_id().empty()) {
    metrics_.RecordRejectedInvalid();
    return absl::InvalidArgumentError(
        "request_id is for SubmitJob: a Quantize job ends with its call, so a retried Quantize "
        "is a new job");
  }
  return AdmitJob(submission.peer, submission.principal, parsed->message, submission.raw.size,
                  /*bound_to_call=*/true);
}

void JobService::Submit(JobSubmission submission) {
  auto shared = std::make_shared<JobSubmission>(std::move(submission));
  const int64_t size = shared->raw.size;
  if (!Dispatch(size, [this, shared] { AdmitSubmission(shared); })) {
    Discard(shared->raw);
    shared->answer(DispatchRefused(size));
  }
}

void JobService::AdmitSubmission(const std::shared_ptr<JobSubmission>& submission) {
  // Decided in its own scope so that the parsed request and its reservation are gone before the
  // caller hears the outcome: a refused request holds no memory once it is answered.
  std::optional<JobSubmission::Outcome> outcome = DecideSubmission(submission);
  if (outcome.has_value()) submission->answer(*outcome);
}

std::optional<JobSubmission::Outcome> JobService::DecideSubmission(
    const std::shared_ptr<JobSubmission>& submission) {
  const JobSubmission& s = *submission;
  if (s.abandoned && s.abandoned()) return CancelledBeforeAdmission();
  absl::StatusOr<ParsedRequest<v1::QuantizeRequest>> parsed =
      ParseWithinBudget<v1::QuantizeRequest>(submission->raw, memory_);
  if (!parsed.ok()) {
    if (absl::IsInvalidArgument(parsed.status())) metrics_.RecordRejectedInvalid();
    return parsed.status();
  }
  v1::QuantizeRequest& request = parsed->message;
  const int64_t size = submission->raw.size;
  if (request.request_id().empty()) {
    return AdmitJob(s.peer, s.principal, request, size, /*bound_to_call=*/false);
  }
  if (absl::Status valid = ValidateRequestId(request.request_id()); !valid.ok()) {
    metrics_.RecordRejectedInvalid();
    return valid;
  }
  // The fingerprint covers everything but the id itself.
  std::string request_id = std::move(*request.mutable_request_id());
  request.clear_request_id();
  std::string fingerprint = RequestFingerprint(request);
  request.set_request_id(request_id);
  RequestIds::Decision decision = request_ids_.Begin(
      s.principal.name, request_id, fingerprint,
      [submission](RequestIds::Outcome outcome) { submission->answer(outcome); });
  if (decision.outcome.has_value()) return *decision.outcome;
  if (!decision.ticket.has_value()) return std::nullopt;  // the first call with this id answers
  const absl::StatusOr<std::shared_ptr<Job>> job =
      AdmitJob(s.peer, s.principal, request, size, /*bound_to_call=*/false, fingerprint);
  request_ids_.Complete(*decision.ticket, job);
  return job;
}

void JobService::CreateMesh(MeshCreation creation) {
  auto shared = std::make_shared<MeshCreation>(std::move(creation));
  const int64_t size = shared->raw.size;
  const bool dispatched = Dispatch(size, [this, shared] {
    // Decided first, answered after: the parsed request's reservation is gone by then.
    const absl::StatusOr<v1::Mesh> created = AdmitCreateMesh(*shared);
    shared->answer(created);
  });
  if (!dispatched) {
    Discard(shared->raw);
    shared->answer(DispatchRefused(size));
  }
}

absl::StatusOr<v1::Mesh> JobService::AdmitCreateMesh(MeshCreation& creation) {
  if (creation.abandoned && creation.abandoned()) return CancelledBeforeAdmission();
  if (creation.mesh_offset > 0) return AdmitUploadedMesh(creation);
  absl::StatusOr<ParsedRequest<v1::CreateMeshRequest>> parsed =
      ParseWithinBudget<v1::CreateMeshRequest>(creation.raw, memory_);
  if (!parsed.ok()) return parsed.status();
  absl::StatusOr<AdmittedMesh> mesh = StoreableMesh(parsed->message.mesh(), creation.raw.size);
  return StoreMesh(std::move(mesh), parsed->message.mesh(), creation.principal);
}

absl::StatusOr<v1::Mesh> JobService::AdmitUploadedMesh(MeshCreation& creation) {
  // Decoded from the bytes as they arrived, never parsed as one message: the bytes and the
  // decoded mesh are all the upload costs (the parsed message was 5x the decoded mesh at 1M arcs).
  const RequestBytes& bytes = *creation.raw.bytes;
  const int64_t offset = creation.mesh_offset;
  const TMeshBytesReader read = [&bytes, offset] {
    std::unique_ptr<google::protobuf::io::ZeroCopyInputStream> stream = bytes.Read();
    stream->Skip(static_cast<int>(offset));
    return stream;
  };
  absl::StatusOr<MemoryReservation> memory =
      memory_.Reserve(MemoryUse::kStoredMeshes, MeshBytes(creation.raw.size - offset), "the mesh");
  if (!memory.ok()) {
    Discard(creation.raw);
    return memory.status();
  }
  absl::StatusOr<AdmittedMesh> mesh = AdmitMeshBytes(read, limits_.max_arcs, *std::move(memory));
  const MeshBytesSource serialized([&read] {
    std::string mesh_bytes;
    std::unique_ptr<google::protobuf::io::ZeroCopyInputStream> in = read();
    const void* data;
    int size;
    while (in->Next(&data, &size)) mesh_bytes.append(static_cast<const char*>(data), size);
    return mesh_bytes;
  });
  absl::StatusOr<v1::Mesh> answer = StoreMesh(std::move(mesh), serialized, creation.principal);
  Discard(creation.raw);
  return answer;
}

absl::StatusOr<v1::Mesh> JobService::StoreMesh(absl::StatusOr<AdmittedMesh> mesh,
                                               const MeshBytesSource& bytes,
                                               const Principal& principal) {
  if (!mesh.ok()) {
    if (absl::IsInvalidArgument(mesh.status())) metrics_.RecordRejectedInvalid();
    return mesh.status();
  }
  absl::StatusOr<std::shared_ptr<const StoredMesh>> stored =
      meshes_.Add(*std::move(mesh), bytes, principal.name, absl::Now());
  if (!stored.ok()) return stored.status();
  v1::Mesh answer = MeshToProto(**stored);
  spdlog::info("event=mesh_created mesh={} owner={} display_name={} arcs={}", answer.name(),
               QuotedLogValue(answer.owner()), QuotedLogValue(answer.display_name()),
               answer.mesh_stats().arcs());
  return answer;
}

absl::StatusOr<AdmittedMesh> JobService::StoreableMesh(const v1::TMesh& proto,
                                                       int64_t request_bytes) {
  if (absl::Status size = CheckMeshSize(proto, limits_.max_arcs); !size.ok()) return size;
  absl::StatusOr<MemoryReservation> memory =
      memory_.Reserve(MemoryUse::kStoredMeshes, MeshBytes(request_bytes), "the mesh");
  if (!memory.ok()) return memory.status();
  return AdmitMesh(proto, limits_.max_arcs, *std::move(memory));
}

absl::StatusOr<JobSpec> JobService::Readmit(const JobClaims::Claim& claim) {
  const Principal owner{.name = claim.owner, .admin = true};
  const AdmissionContext admission{limits_, owner, meshes_, memory_};
  return PrepareJobSpec(claim.request, claim.request_bytes, admission);
}

// ---------------------------------------------------------------------------------------------
// Lookups

absl::StatusOr<std::shared_ptr<Job>> JobService::FindJob(const std::string& name,
                                                         const Principal& principal) {
  absl::StatusOr<std::string> id = ParseResourceName(kJobCollection, name);
  if (!id.ok()) return id.status();
  absl::StatusOr<std::shared_ptr<Job>> found = scheduler_.Lookup(*id);
  if (!found.ok()) {
    // Not NOT_FOUND: the job may well exist, and the client should retry.
    return absl::UnavailableError(
        absl::StrCat("job ", name, " cannot be looked up now: ", found.status().message()));
  }
  std::shared_ptr<Job> job = *std::move(found);
  if (job == nullptr || !principal.CanAccess(job->owner())) {
    return absl::NotFoundError(
        absl::StrCat("job ", name, " not found: never submitted, or ended longer ago than the ",
                     "server keeps finished jobs"));
  }
  return job;
}

absl::StatusOr<WatchTarget> JobService::Watch(const v1::WatchJobRequest& request,
                                              const Principal& principal) {
  if (request.from_event() < 0) {
    return absl::InvalidArgumentError(
        absl::StrCat("from_event ", request.from_event(), " is negative"));
  }
  absl::StatusOr<std::shared_ptr<Job>> job = FindJob(request.name(), principal);
  if (!job.ok()) return job.status();
  return WatchTarget{*std::move(job), request.from_event()};
}

absl::StatusOr<v1::Job> JobService::GetJob(const v1::GetJobRequest& request,
                                           const Principal& principal) {
  absl::StatusOr<std::shared_ptr<Job>> job = FindJob(request.name(), principal);
  if (!job.ok()) return job.status();
  return (*job)->ToProto(request.view() == v1::JOB_VIEW_UNSPECIFIED ? v1::FULL : request.view());
}

absl::StatusOr<v1::ListJobsResponse> JobService::ListJobs(const v1::ListJobsRequest& request,
                                                          const Principal& principal) {
  JobStore::Query query;
  query.page_size = request.page_size();
  query.page_token = request.page_token();
  query.state = request.state();
  query.visible = [&principal](const Job& job) { return principal.CanAccess(job.owner()); };
  absl::StatusOr<JobStore::Page> page = scheduler_.List(query);
  if (!page.ok()) return page.status();
  const v1::JobView view = request.view() == v1::JOB_VIEW_UNSPECIFIED ? v1::BASIC : request.view();
  v1::ListJobsResponse listed;
  int64_t bytes = 0;
  for (const JobStore::Listed& entry : page->jobs) {
    v1::Job job = entry.job->ToProto(view);
    const int64_t size = static_cast<int64_t>(job.ByteSizeLong());
    if (listed.jobs_size() > 0 && bytes + size > kMaxListPageBytes) {
      listed.set_next_page_token(entry.token);  // the page is full: resume at this job
      return listed;
    }
    bytes += size;
    *listed.add_jobs() = std::move(job);
  }
  listed.set_next_page_token(page->next_page_token);
  return listed;
}

absl::StatusOr<v1::Job> JobService::CancelJob(const v1::CancelJobRequest& request,
                                              const Principal& principal) {
  absl::StatusOr<std::shared_ptr<Job>> job = FindJob(request.name(), principal);
  if (!job.ok()) return job.status();
  scheduler_.Cancel(**job);
  return (*job)->ToProto(v1::FULL);
}

absl::StatusOr<v1::Mesh> JobService::GetMesh(const v1::GetMeshRequest& request,
                                             const Principal& principal) {
  absl::StatusOr<std::shared_ptr<const StoredMesh>> stored =
      FindStoredMesh(request.name(), principal, meshes_);
  if (!stored.ok()) return stored.status();
  return MeshToProto(**stored);
}

absl::StatusOr<v1::DeleteMeshResponse> JobService::DeleteMesh(const v1::DeleteMeshRequest& request,
                                                              const Principal& principal) {
  absl::StatusOr<std::shared_ptr<const StoredMesh>> stored =
      FindStoredMesh(request.name(), principal, meshes_);
  if (!stored.ok()) return stored.status();
  if (!meshes_.Remove((*stored)->id)) {
    return absl::NotFoundError(absl::StrCat("mesh ", request.name(), " not found"));
  }
  return v1::DeleteMeshResponse();
}

v1::ServerStats JobService::Stats() const {
  v1::ServerStats stats;
  metrics_.FillProto(stats);
  scheduler_.FillStats(stats);
  stats.set_stored_meshes(meshes_.size());
  *stats.mutable_uptime() =
      TimeUtil::NanosecondsToDuration(absl::ToInt64Nanoseconds(absl::Now() - start_time_));
  stats.set_shutting_down(!scheduler_.accepting());
  *stats.mutable_memory() = memory_.budget().ToProto();
  stats.set_admissions_in_progress(admission_pool_.in_progress());
  return stats;
}

}  // namespace ispq::server
