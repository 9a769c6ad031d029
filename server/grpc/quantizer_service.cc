// SPDX-License-Identifier: Apache-2.0
#include "server/grpc/quantizer_service.h"

#include <cstdint>
#include <limits>
#include <memory>
#include <utility>

#include "absl/status/status.h"
#include "server/grpc/call_principal.h"
#include "server/grpc/grpc_status.h"
#include "server/grpc/job_event_stream.h"
#include "server/grpc/mesh_upload.h"
#include "server/grpc/request_intake.h"

namespace ispq::server {
namespace {

// Lookups (names, paging) are tiny; anything larger is not one.
constexpr int64_t kMaxLookupRequestBytes = 64 << 10;
constexpr int64_t kNoSizeLimit = std::numeric_limits<int64_t>::max();  // gRPC's limit applies

// Answers a unary call with `answer` or its error.
template <typename Response>
void Reply(UnaryCall& call, const absl::StatusOr<Response>& answer) {
  if (answer.ok()) {
    call.Answer(*answer);
  } else {
    call.Fail(answer.status());
  }
}

}  // namespace

QuantizerService::QuantizerService(JobService& service, const Authenticator& authenticator,
                                   int64_t max_upload_bytes, absl::Duration upload_idle)
    : service_(service),
      authenticator_(authenticator),
      max_upload_bytes_(max_upload_bytes),
      upload_watchdog_(upload_idle) {}

std::optional<QuantizerService::AcceptedRequest> QuantizerService::Accept(
    UnaryCall& call, const grpc::ByteBuffer* request, int64_t max_bytes) {
  absl::StatusOr<Principal> principal = CallPrincipal(authenticator_, call.context());
  if (!principal.ok()) {
    call.Fail(principal.status());
    return std::nullopt;
  }
  absl::StatusOr<RawRequest> raw = TakeRequest(request, max_bytes, service_.memory());
  if (!raw.ok()) {
    call.Fail(raw.status());
    return std::nullopt;
  }
  return AcceptedRequest{*std::move(principal), *std::move(raw)};
}

// ---------------------------------------------------------------------------------------------
// Requests that carry a mesh

grpc::ServerWriteReactor<grpc::ByteBuffer>* QuantizerService::Quantize(
    grpc::CallbackServerContext* context, const grpc::ByteBuffer* request) {
  std::shared_ptr<JobEventStream> stream =
      JobEventStream::Create(&service_.scheduler(), &service_.memory().budget());
  absl::StatusOr<Principal> principal = CallPrincipal(authenticator_, *context);
  if (!principal.ok()) {
    stream->Reject(ToGrpcStatus(principal.status()));
    return stream.get();
  }
  absl::StatusOr<RawRequest> raw = TakeRequest(request, kNoSizeLimit, service_.memory());
  if (!raw.ok()) {
    stream->Reject(ToGrpcStatus(raw.status(), *context));
    return stream.get();
  }
  JobSubmission submission;
  submission.principal = *std::move(principal);
  submission.raw = *std::move(raw);
  submission.peer = context->peer();
  // The stream does not finish the call before its job is attached or the call rejected, so the
  // context outlives admission.
  submission.abandoned = [context] { return context->IsCancelled(); };
  submission.answer = [context, stream](const JobSubmission::Outcome& job) {
    if (!job.ok()) {
      stream->Reject(ToGrpcStatus(job.status(), *context));
      return;
    }
    // A call that is already over (its deadline passed during admission) cancels the job here.
    stream->Attach(*job, /*from_event=*/0);
  };
  service_.Quantize(std::move(submission));
  return stream.get();
}

grpc::ServerUnaryReactor* QuantizerService::SubmitJob(grpc::CallbackServerContext* context,
                                                      const grpc::ByteBuffer* request,
                                                      grpc::ByteBuffer* response) {
  auto* call = new UnaryCall(context, response, &service_.memory());
  std::optional<AcceptedRequest> accepted = Accept(*call, request, kNoSizeLimit);
  if (!accepted.has_value()) return call;
  JobSubmission submission;
  submission.principal = std::move(accepted->principal);
  submission.raw = std::move(accepted->raw);
  submission.peer = context->peer();
  submission.abandoned = [context] { return context->IsCancelled(); };
  submission.answer = [call](const JobSubmission::Outcome& job) {
    if (job.ok()) {
      call->Answer((*job)->ToProto(v1::FULL));
    } else {
      call->Fail(job.status());
    }
  };
  service_.Submit(std::move(submission));
  return call;
}

grpc::ServerUnaryReactor* QuantizerService::CreateMesh(grpc::CallbackServerContext* context,
                                                       const grpc::ByteBuffer* request,
                                                       grpc::ByteBuffer* response) {
  auto* call = new UnaryCall(context, response, &service_.memory());
  std::optional<AcceptedRequest> accepted = Accept(*call, request, kNoSizeLimit);
  if (!accepted.has_value()) return call;
  MeshCreation creation;
  creation.principal = std::move(accepted->principal);
  creation.raw = std::move(accepted->raw);
  creation.abandoned = [context] { return context->IsCancelled(); };
  creation.answer = [call](const absl::StatusOr<v1::Mesh>& mesh) { Reply(*call, mesh); };
  service_.CreateMesh(std::move(creation));
  return call;
}

grpc::ServerReadReactor<grpc::ByteBuffer>* QuantizerService::UploadMesh(
    grpc::CallbackServerContext* context, grpc::ByteBuffer* response) {
  absl::StatusOr<Principal> principal = CallPrincipal(authenticator_, *context);
  if (!principal.ok()) {
    // Refused before a byte is read: a reactor that only finishes.
    class Refused final : public grpc::ServerReadReactor<grpc::ByteBuffer> {
     public:
      explicit Refused(const grpc::Status& status) { Finish(status); }
      void OnDone() override { delete this; }
    };
    return new Refused(ToGrpcStatus(principal.status(), *context));
  }
  return new MeshUpload(context, response, *std::move(principal), service_, upload_watchdog_,
                        max_upload_bytes_);
}

// ---------------------------------------------------------------------------------------------
// Lookups

template <typename Request, typename Handler>
grpc::ServerUnaryReactor* QuantizerService::Lookup(grpc::CallbackServerContext* context,
                                                   const grpc::ByteBuffer* request,
                                                   grpc::ByteBuffer* response, Handler handler) {
  auto* call = new UnaryCall(context, response, &service_.memory());
  std::optional<AcceptedRequest> accepted = Accept(*call, request, kMaxLookupRequestBytes);
  if (!accepted.has_value()) return call;
  absl::StatusOr<ParsedRequest<Request>> parsed =
      ParseWithinBudget<Request>(accepted->raw, service_.memory());
  if (!parsed.ok()) {
    call->Fail(parsed.status());
    return call;
  }
  // The service, not this adapter: a store-call thread may run this after the gRPC server and
  // the adapter are gone, the service (which joins those threads) not.
  const bool scheduled =
      service_.OffTransportThread([call, handler, service = &service_, parsed = *std::move(parsed),
                                   principal = std::move(accepted->principal)]() mutable {
        Reply(*call, handler(*service, parsed.message, principal));
      });
  if (!scheduled) call->Fail(service_.StoreCallsFull());
  return call;
}

grpc::ServerWriteReactor<grpc::ByteBuffer>* QuantizerService::WatchJob(
    grpc::CallbackServerContext* context, const grpc::ByteBuffer* request) {
  std::shared_ptr<JobEventStream> stream =
      JobEventStream::Create(/*cancel_job_with_call=*/nullptr, &service_.memory().budget());
  absl::StatusOr<WatchCall> accepted = AcceptWatch(*context, request);
  if (!accepted.ok()) {
    stream->Reject(ToGrpcStatus(accepted.status(), *context));
    return stream.get();
  }
  const bool scheduled = service_.OffTransportThread(
      [service = &service_, context, stream, accepted = *std::move(accepted)]() mutable {
        absl::StatusOr<WatchTarget> watched = service->Watch(accepted.request, accepted.principal);
        if (!watched.ok()) {
          stream->Reject(ToGrpcStatus(watched.status(), *context));
        } else {
          stream->Attach(std::move(watched->job), watched->from_event);
        }
      });
  if (!scheduled) stream->Reject(ToGrpcStatus(service_.StoreCallsFull(), *context));
  return stream.get();
}

absl::StatusOr<QuantizerService::WatchCall> QuantizerService::AcceptWatch(
    grpc::CallbackServerContext& context, const grpc::ByteBuffer* request) {
  absl::StatusOr<Principal> principal = CallPrincipal(authenticator_, context);
  if (!principal.ok()) return principal.status();
  absl::StatusOr<RawRequest> raw = TakeRequest(request, kMaxLookupRequestBytes, service_.memory());
  if (!raw.ok()) return raw.status();
  absl::StatusOr<ParsedRequest<v1::WatchJobRequest>> parsed =
      ParseWithinBudget<v1::WatchJobRequest>(*raw, service_.memory());
  if (!parsed.ok()) return parsed.status();
  return WatchCall{*std::move(principal), std::move(parsed->message)};
}

grpc::ServerUnaryReactor* QuantizerService::GetJob(grpc::CallbackServerContext* context,
                                                   const grpc::ByteBuffer* request,
                                                   grpc::ByteBuffer* response) {
  return Lookup<v1::GetJobRequest>(
      context, request, response,
      [](JobService& service, const v1::GetJobRequest& get, const Principal& principal) {
        return service.GetJob(get, principal);
      });
}

grpc::ServerUnaryReactor* QuantizerService::ListJobs(grpc::CallbackServerContext* context,
                                                     const grpc::ByteBuffer* request,
                                                     grpc::ByteBuffer* response) {
  return Lookup<v1::ListJobsRequest>(
      context, request, response,
      [](JobService& service, const v1::ListJobsRequest& list, const Principal& principal) {
        return service.ListJobs(list, principal);
      });
}

grpc::ServerUnaryReactor* QuantizerService::CancelJob(grpc::CallbackServerContext* context,
                                                      const grpc::ByteBuffer* request,
                                                      grpc::ByteBuffer* response) {
  return Lookup<v1::CancelJobRequest>(
      context, request, response,
      [](JobService& service, const v1::CancelJobRequest& cancel, const Principal& principal) {
        return service.CancelJob(cancel, principal);
      });
}

grpc::ServerUnaryReactor* QuantizerService::GetMesh(grpc::CallbackServerContext* context,
                                                    const grpc::ByteBuffer* request,
                                                    grpc::ByteBuffer* response) {
  return Lookup<v1::GetMeshRequest>(
      context, request, response,
      [](JobService& service, const v1::GetMeshRequest& get, const Principal& principal) {
        return service.GetMesh(get, principal);
      });
}

grpc::ServerUnaryReactor* QuantizerService::DeleteMesh(grpc::CallbackServerContext* context,
                                                       const grpc::ByteBuffer* request,
                                                       grpc::ByteBuffer* response) {
  return Lookup<v1::DeleteMeshRequest>(
      context, request, response,
      [](JobService& service, const v1::DeleteMeshRequest& remove, const Principal& principal) {
        return service.DeleteMesh(remove, principal);
      });
}

grpc::ServerUnaryReactor* QuantizerService::GetServerStats(grpc::CallbackServerContext* context,
                                                           const grpc::ByteBuffer* request,
                                                           grpc::ByteBuffer* response) {
  return Lookup<v1::GetServerStatsRequest>(
      context, request, response,
      [](JobService& service, const v1::GetServerStatsRequest&,
         const Principal&) -> absl::StatusOr<v1::ServerStats> { return service.Stats(); });
}

}  // namespace ispq::server
