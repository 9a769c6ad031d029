// The ispq.v1.Quantizer service on gRPC's callback API: each method checks the bearer token,
// turns its request into calls on the scheduler and the mesh store, and answers. No method
// blocks a gRPC thread on a solve: unary methods only validate and look things up, and the two
// streaming methods hand the call to a JobEventStream that the job wakes up.
//
// Methods are registered raw (see server/raw_proto_call.h) so that a request that does not
// parse is INVALID_ARGUMENT; each raw method parses its request and calls a typed handler.
// Errors cross into gRPC here and only here.
#ifndef ISPQ_SERVER_QUANTIZER_SERVICE_H_
#define ISPQ_SERVER_QUANTIZER_SERVICE_H_

#include <memory>
#include <string>

#include "absl/status/statusor.h"
#include "absl/time/time.h"
#include "grpcpp/support/byte_buffer.h"
#include "ispq/v1/service.grpc.pb.h"
#include "server/bearer_token_authenticator.h"
#include "server/job_scheduler.h"
#include "server/job_spec.h"
#include "server/mesh_store.h"
#include "server/server_metrics.h"

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

class QuantizerService final : public RawQuantizerService {
 public:
  // Everything referenced must outlive the gRPC server that serves this service.
  QuantizerService(JobScheduler& scheduler, MeshStore& meshes, ServerMetrics& metrics,
                   const BearerTokenAuthenticator& authenticator, JobLimits limits);

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

 private:
  // Validates and queues a job; on a full queue also sets the retry trailer on `context`.
  absl::StatusOr<std::shared_ptr<Job>> Admit(grpc::CallbackServerContext& context,
                                             const v1::QuantizeRequest& request,
                                             bool bound_to_call);
  absl::StatusOr<std::shared_ptr<Job>> FindJob(const std::string& name);
  absl::StatusOr<std::shared_ptr<const StoredMesh>> FindMesh(const std::string& name);
  // Answers a unary method: token check, parse, `handler`, serialize.
  template <typename Request, typename Handler>
  grpc::ServerUnaryReactor* Unary(grpc::CallbackServerContext* context,
                                  const grpc::ByteBuffer* request, grpc::ByteBuffer* response,
                                  Handler&& handler);

  JobScheduler& scheduler_;
  MeshStore& meshes_;
  ServerMetrics& metrics_;
  const BearerTokenAuthenticator& authenticator_;
  const JobLimits limits_;
  const absl::Time start_time_;
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_QUANTIZER_SERVICE_H_
