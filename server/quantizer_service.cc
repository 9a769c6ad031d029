#include "server/quantizer_service.h"

#include <string>
#include <utility>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "absl/time/clock.h"
#include "google/protobuf/util/time_util.h"
#include "server/grpc_status.h"
#include "server/job_event_stream.h"
#include "server/log_value.h"
#include "server/mesh_admission.h"
#include "server/raw_proto_call.h"
#include "server/resource_names.h"
#include "spdlog/spdlog.h"

namespace ispq::server {
namespace {

using google::protobuf::util::TimeUtil;

// A stream that ends before its first event: bad request, full queue, unknown job.
class RejectedStream : public grpc::ServerWriteReactor<grpc::ByteBuffer> {
 public:
  explicit RejectedStream(grpc::Status status) { Finish(std::move(status)); }
  void OnDone() override { delete this; }
};

v1::Mesh MeshToProto(const StoredMesh& stored) {
  v1::Mesh proto;
  proto.set_name(ResourceName(kMeshCollection, stored.id));
  proto.set_display_name(stored.admitted.mesh->name());
  *proto.mutable_mesh_stats() = stored.admitted.stats;
  *proto.mutable_create_time() =
      TimeUtil::NanosecondsToTimestamp(absl::ToUnixNanos(stored.create_time));
  return proto;
}

}  // namespace

QuantizerService::QuantizerService(JobScheduler& scheduler, MeshStore& meshes,
                                   ServerMetrics& metrics,
                                   const BearerTokenAuthenticator& authenticator, JobLimits limits)
    : scheduler_(scheduler),
      meshes_(meshes),
      metrics_(metrics),
      authenticator_(authenticator),
      limits_(limits),
      start_time_(absl::Now()) {}

template <typename Request, typename Handler>
grpc::ServerUnaryReactor* QuantizerService::Unary(grpc::CallbackServerContext* context,
                                                  const grpc::ByteBuffer* request,
                                                  grpc::ByteBuffer* response, Handler&& handler) {
  if (grpc::Status auth = authenticator_.Check(*context); !auth.ok()) {
    grpc::ServerUnaryReactor* reactor = context->DefaultReactor();
    reactor->Finish(std::move(auth));
    return reactor;
  }
  return AnswerUnary<Request>(context, *request, response, std::forward<Handler>(handler));
}

absl::StatusOr<std::shared_ptr<Job>> QuantizerService::Admit(grpc::CallbackServerContext& context,
                                                             const v1::QuantizeRequest& request,
                                                             bool bound_to_call) {
  absl::StatusOr<JobSpec> spec = PrepareJobSpec(request, limits_, meshes_);
  if (!spec.ok()) {
    if (absl::IsInvalidArgument(spec.status())) metrics_.RecordRejectedInvalid();
    spdlog::debug("event=job_rejected peer={} code={} error={}", context.peer(),
                  absl::StatusCodeToString(spec.status().code()),
                  QuotedLogValue(std::string(spec.status().message())));
    return spec.status();
  }
  absl::StatusOr<std::shared_ptr<Job>> job = scheduler_.Submit(*std::move(spec), bound_to_call);
  if (absl::IsResourceExhausted(job.status())) {
    // gRFC A6: a client with a retry policy waits this long before retrying.
    context.AddTrailingMetadata("grpc-retry-pushback-ms",
                                absl::StrCat(absl::ToInt64Milliseconds(scheduler_.RetryHint())));
  }
  return job;
}

absl::StatusOr<std::shared_ptr<Job>> QuantizerService::FindJob(const std::string& name) {
  absl::StatusOr<std::string> id = ParseResourceName(kJobCollection, name);
  if (!id.ok()) return id.status();
  std::shared_ptr<Job> job = scheduler_.Find(*id);
  if (job == nullptr) {
    return absl::NotFoundError(
        absl::StrCat("job ", name, " not found: never submitted, or ended longer ago than the ",
                     "server keeps finished jobs"));
  }
  return job;
}

absl::StatusOr<std::shared_ptr<const StoredMesh>> QuantizerService::FindMesh(
    const std::string& name) {
  absl::StatusOr<std::string> id = ParseResourceName(kMeshCollection, name);
  if (!id.ok()) return id.status();
  std::shared_ptr<const StoredMesh> stored = meshes_.Find(*id);
  if (stored == nullptr) return absl::NotFoundError(absl::StrCat("mesh ", name, " not found"));
  return stored;
}

grpc::ServerWriteReactor<grpc::ByteBuffer>* QuantizerService::Quantize(
    grpc::CallbackServerContext* context, const grpc::ByteBuffer* raw_request) {
  if (grpc::Status auth = authenticator_.Check(*context); !auth.ok()) {
    return new RejectedStream(std::move(auth));
  }
  absl::StatusOr<v1::QuantizeRequest> request = ParseRequest<v1::QuantizeRequest>(*raw_request);
  if (!request.ok()) return new RejectedStream(ToGrpcStatus(request.status()));
  absl::StatusOr<std::shared_ptr<Job>> job = Admit(*context, *request, /*bound_to_call=*/true);
  if (!job.ok()) return new RejectedStream(ToGrpcStatus(job.status()));
  // A call that is already over (its deadline passed during validation) still gets OnCancel,
  // which cancels the job.
  return JobEventStream::Start(*std::move(job), /*from_event=*/0, &scheduler_);
}

grpc::ServerWriteReactor<grpc::ByteBuffer>* QuantizerService::WatchJob(
    grpc::CallbackServerContext* context, const grpc::ByteBuffer* raw_request) {
  if (grpc::Status auth = authenticator_.Check(*context); !auth.ok()) {
    return new RejectedStream(std::move(auth));
  }
  absl::StatusOr<v1::WatchJobRequest> request = ParseRequest<v1::WatchJobRequest>(*raw_request);
  if (!request.ok()) return new RejectedStream(ToGrpcStatus(request.status()));
  if (request->from_event() < 0) {
    return new RejectedStream(
        grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                     absl::StrCat("from_event ", request->from_event(), " is negative")));
  }
  absl::StatusOr<std::shared_ptr<Job>> job = FindJob(request->name());
  if (!job.ok()) return new RejectedStream(ToGrpcStatus(job.status()));
  return JobEventStream::Start(*std::move(job), request->from_event(),
                               /*cancel_job_with_call=*/nullptr);
}

grpc::ServerUnaryReactor* QuantizerService::SubmitJob(grpc::CallbackServerContext* context,
                                                      const grpc::ByteBuffer* request,
                                                      grpc::ByteBuffer* response) {
  return Unary<v1::QuantizeRequest>(
      context, request, response,
      [&](const v1::QuantizeRequest& submit) -> absl::StatusOr<v1::Job> {
        absl::StatusOr<std::shared_ptr<Job>> job = Admit(*context, submit, /*bound_to_call=*/false);
        if (!job.ok()) return job.status();
        return (*job)->ToProto(v1::FULL);
      });
}

grpc::ServerUnaryReactor* QuantizerService::GetJob(grpc::CallbackServerContext* context,
                                                   const grpc::ByteBuffer* request,
                                                   grpc::ByteBuffer* response) {
  return Unary<v1::GetJobRequest>(
      context, request, response, [&](const v1::GetJobRequest& get) -> absl::StatusOr<v1::Job> {
        absl::StatusOr<std::shared_ptr<Job>> job = FindJob(get.name());
        if (!job.ok()) return job.status();
        return (*job)->ToProto(get.view() == v1::JOB_VIEW_UNSPECIFIED ? v1::FULL : get.view());
      });
}

grpc::ServerUnaryReactor* QuantizerService::ListJobs(grpc::CallbackServerContext* context,
                                                     const grpc::ByteBuffer* request,
                                                     grpc::ByteBuffer* response) {
  return Unary<v1::ListJobsRequest>(
      context, request, response,
      [&](const v1::ListJobsRequest& list) -> absl::StatusOr<v1::ListJobsResponse> {
        absl::StatusOr<JobStore::Page> page =
            scheduler_.List(list.page_size(), list.page_token(), list.state());
        if (!page.ok()) return page.status();
        const v1::JobView view = list.view() == v1::JOB_VIEW_UNSPECIFIED ? v1::BASIC : list.view();
        v1::ListJobsResponse listed;
        for (const std::shared_ptr<Job>& job : page->jobs) *listed.add_jobs() = job->ToProto(view);
        listed.set_next_page_token(page->next_page_token);
        return listed;
      });
}

grpc::ServerUnaryReactor* QuantizerService::CancelJob(grpc::CallbackServerContext* context,
                                                      const grpc::ByteBuffer* request,
                                                      grpc::ByteBuffer* response) {
  return Unary<v1::CancelJobRequest>(
      context, request, response,
      [&](const v1::CancelJobRequest& cancel) -> absl::StatusOr<v1::Job> {
        absl::StatusOr<std::shared_ptr<Job>> job = FindJob(cancel.name());
        if (!job.ok()) return job.status();
        scheduler_.Cancel(**job);
        return (*job)->ToProto(v1::FULL);
      });
}

grpc::ServerUnaryReactor* QuantizerService::CreateMesh(grpc::CallbackServerContext* context,
                                                       const grpc::ByteBuffer* request,
                                                       grpc::ByteBuffer* response) {
  return Unary<v1::CreateMeshRequest>(
      context, request, response,
      [&](const v1::CreateMeshRequest& create) -> absl::StatusOr<v1::Mesh> {
        absl::StatusOr<AdmittedMesh> admitted = AdmitMesh(create.mesh(), limits_.max_arcs);
        if (!admitted.ok()) {
          metrics_.RecordRejectedInvalid();
          return admitted.status();
        }
        std::shared_ptr<const StoredMesh> stored = meshes_.Add(*std::move(admitted), absl::Now());
        v1::Mesh mesh = MeshToProto(*stored);
        spdlog::info("event=mesh_created mesh={} display_name={} arcs={}", mesh.name(),
                     QuotedLogValue(mesh.display_name()), mesh.mesh_stats().arcs());
        return mesh;
      });
}

grpc::ServerUnaryReactor* QuantizerService::GetMesh(grpc::CallbackServerContext* context,
                                                    const grpc::ByteBuffer* request,
                                                    grpc::ByteBuffer* response) {
  return Unary<v1::GetMeshRequest>(
      context, request, response, [&](const v1::GetMeshRequest& get) -> absl::StatusOr<v1::Mesh> {
        absl::StatusOr<std::shared_ptr<const StoredMesh>> stored = FindMesh(get.name());
        if (!stored.ok()) return stored.status();
        return MeshToProto(**stored);
      });
}

grpc::ServerUnaryReactor* QuantizerService::DeleteMesh(grpc::CallbackServerContext* context,
                                                       const grpc::ByteBuffer* request,
                                                       grpc::ByteBuffer* response) {
  return Unary<v1::DeleteMeshRequest>(
      context, request, response,
      [&](const v1::DeleteMeshRequest& remove) -> absl::StatusOr<v1::DeleteMeshResponse> {
        absl::StatusOr<std::string> id = ParseResourceName(kMeshCollection, remove.name());
        if (!id.ok()) return id.status();
        if (!meshes_.Remove(*id)) {
          return absl::NotFoundError(absl::StrCat("mesh ", remove.name(), " not found"));
        }
        return v1::DeleteMeshResponse();
      });
}

grpc::ServerUnaryReactor* QuantizerService::GetServerStats(grpc::CallbackServerContext* context,
                                                           const grpc::ByteBuffer* request,
                                                           grpc::ByteBuffer* response) {
  return Unary<v1::GetServerStatsRequest>(
      context, request, response,
      [&](const v1::GetServerStatsRequest&) -> absl::StatusOr<v1::ServerStats> {
        v1::ServerStats stats;
        metrics_.FillProto(stats);
        scheduler_.FillStats(stats);
        stats.set_stored_meshes(meshes_.size());
        *stats.mutable_uptime() =
            TimeUtil::NanosecondsToDuration(absl::ToInt64Nanoseconds(absl::Now() - start_time_));
        stats.set_shutting_down(!scheduler_.accepting());
        return stats;
      });
}

}  // namespace ispq::server
