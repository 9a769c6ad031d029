// SPDX-License-Identifier: Apache-2.0
// The ispq.v1.Quantizer service on gRPC's callback API: the gRPC adapter over the
// transport-neutral JobService (server/service/job_service.h). Each method authenticates its
// caller (server/grpc/call_principal.h), takes its request's bytes out of the call within the
// memory budget (server/grpc/request_intake.h), calls the service and answers, turning its
// absl::Status into a grpc::Status (server/grpc/grpc_status.h). No method blocks a gRPC thread on
// a solve or on a database: requests that carry a mesh (Quantize, SubmitJob, CreateMesh) are
// admitted by the service off gRPC's threads when large, lookups are parsed on gRPC's thread and
// answered there or, with a shared store, on the service's store-call threads. UploadMesh
// streams a large mesh in (server/grpc/mesh_upload.h). The two server-streaming
// methods hand the call to a JobEventStream that the job wakes up; a Quantize call is answered at
// once and its job attached (or the call rejected) when admission ends, and the job is cancelled
// with the call.
//
// Methods are registered raw (see server/grpc/raw_proto_call.h) so that a request that does not
// parse is INVALID_ARGUMENT.
#ifndef ISPQ_SERVER_GRPC_QUANTIZER_SERVICE_H_
#define ISPQ_SERVER_GRPC_QUANTIZER_SERVICE_H_

#include <cstdint>
#include <optional>

#include "grpcpp/support/byte_buffer.h"
#include "ispq/v1/service.grpc.pb.h"
#include "server/admission/raw_request.h"
#include "server/auth/authenticator.h"
#include "server/auth/principal.h"
#include "server/grpc/unary_call.h"
#include "server/grpc/upload_watchdog.h"
#include "server/service/job_service.h"

namespace ispq::server {

// Every method of ispq.v1.Quantizer, raw.
using RawQuantizerService = v1::Quantizer::WithRawCallbackMethod_Quantize<
    v1::Quantizer::WithRawCallbackMethod_SubmitJob<v1::Quantizer::WithRawCallbackMethod_WatchJob<
        v1::Quantizer::WithRawCallbackMethod_GetJob<v1::Quantizer::WithRawCallbackMethod_ListJobs<
            v1::Quantizer::WithRawCallbackMethod_CancelJob<
                v1::Quantizer::WithRawCallbackMethod_CreateMesh<
                    v1::Quantizer::WithRawCallbackMethod_GetMesh<
                        v1::Quantizer::WithRawCallbackMethod_DeleteMesh<
                            v1::Quantizer::WithRawCallbackMethod_UploadMesh<
                                v1::Quantizer::WithRawCallbackMethod_GetServerStats<
                                    v1::Quantizer::Service>>>>>>>>>>>;

class QuantizerService final : public RawQuantizerService {
 public:
  // `service` and `authenticator` must outlive the gRPC server that serves this, and `service`
  // this too (its admission threads may still answer calls). Uploads (UploadMesh) may declare at
  // most `max_upload_bytes` and are dropped after `upload_idle` without a chunk.
  QuantizerService(JobService& service, const Authenticator& authenticator,
                   int64_t max_upload_bytes = int64_t{1} << 30,
                   absl::Duration upload_idle = absl::Seconds(60));

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
  grpc::ServerReadReactor<grpc::ByteBuffer>* UploadMesh(grpc::CallbackServerContext* context,
                                                        grpc::ByteBuffer* response) override;
  grpc::ServerUnaryReactor* GetServerStats(grpc::CallbackServerContext* context,
                                           const grpc::ByteBuffer* request,
                                           grpc::ByteBuffer* response) override;

 private:
  // What every unary method does first: the caller's principal and the request's bytes (at most
  // `max_bytes`, counted in the memory budget). Nothing if either fails; `call` has then failed.
  struct AcceptedRequest {
    Principal principal;
    RawRequest raw;
  };
  std::optional<AcceptedRequest> Accept(UnaryCall& call, const grpc::ByteBuffer* request,
                                        int64_t max_bytes);

  // A lookup: authenticate, take and parse `Request` on gRPC's thread, answer with
  // `handler(service, request, principal)` (-> StatusOr<Response>) there or on a store-call
  // thread.
  template <typename Request, typename Handler>
  grpc::ServerUnaryReactor* Lookup(grpc::CallbackServerContext* context,
                                   const grpc::ByteBuffer* request, grpc::ByteBuffer* response,
                                   Handler handler);

  // The caller and the WatchJob request of a call.
  struct WatchCall {
    Principal principal;
    v1::WatchJobRequest request;
  };
  absl::StatusOr<WatchCall> AcceptWatch(grpc::CallbackServerContext& context,
                                        const grpc::ByteBuffer* request);

  JobService& service_;
  const Authenticator& authenticator_;
  const int64_t max_upload_bytes_;
  UploadWatchdog upload_watchdog_;
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_GRPC_QUANTIZER_SERVICE_H_
