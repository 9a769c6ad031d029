// SPDX-License-Identifier: Apache-2.0
// A C++ client of the ispq quantization service (proto/ispq/v1/service.proto): what the `ispq`
// command line uses, so that other C++ programs can call the service the same way.
//
// Streaming calls hand each event to a callback as it arrives and return a JobOutcome that
// says how the job ended, or where the stream broke so that it can be resumed. FollowJob does
// that resumption itself, which is how a client makes sure it never loses a result:
//
//   QuantizerClient client(channel);
//   absl::StatusOr<v1::Job> job = client.SubmitJob(request);
//   JobOutcome outcome = client.FollowJob(job->name(), 0, {.on_event = ShowProgress});
//   if (outcome.result.has_value()) Use(*outcome.result);
//
// Errors are the server's gRPC status as absl::Status (same code and message). A client is
// thread-safe: calls may run concurrently on one instance and one channel.
#ifndef ISPQ_CLIENT_QUANTIZER_CLIENT_H_
#define ISPQ_CLIENT_QUANTIZER_CLIENT_H_

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "absl/time/time.h"
#include "client/server_connection.h"
#include "grpcpp/channel.h"
#include "ispq/v1/service.grpc.pb.h"

namespace ispq::client {

// Called for each event in order; returning false stops the stream (the client cancels the
// call: for Quantize that cancels the job, for WatchJob it only stops watching).
using EventHandler = std::function<bool(const v1::QuantizeEvent& event)>;

struct StreamOptions {
  EventHandler on_event;                              // may be empty
  absl::Duration timeout = absl::InfiniteDuration();  // the call's deadline
};

// How a streamed job ended, or how far its stream got.
struct JobOutcome {
  std::string job;  // "jobs/{id}", once any event arrived (or as given to WatchJob)
  // The result event, if the job produced one (also for a cancelled job that had started).
  std::optional<v1::QuantizationResult> result;
  // OK with a result. Otherwise the job's error if job_ended, or why the stream broke.
  absl::Status status;
  bool job_ended = false;  // a terminal event (result or error) arrived
  int64_t next_event = 0;  // resume with WatchJob(job, next_event) if !job_ended
};

// A gRPC status as an absl::Status with the same code and message.
absl::Status StatusFromGrpc(const grpc::Status& status);

class QuantizerClient {
 public:
  // `auth_token`, if not empty, is sent as a bearer token. `unary_timeout` bounds every
  // non-streaming call.
  explicit QuantizerClient(std::shared_ptr<grpc::Channel> channel, std::string auth_token = "",
                           absl::Duration unary_timeout = absl::Seconds(60));
  static absl::StatusOr<QuantizerClient> Connect(const ServerConnection& connection);

  // Runs a job bound to this call: it is cancelled if the call ends early (timeout, handler
  // stop, process exit).
  JobOutcome Quantize(const v1::QuantizeRequest& request, const StreamOptions& options);
  // Streams a job's events from `from_event`; stopping does not cancel the job.
  JobOutcome WatchJob(const std::string& job, int64_t from_event, const StreamOptions& options);
  // WatchJob until the job ends, resuming after broken streams (UNAVAILABLE, INTERNAL, UNKNOWN:
  // a restarting proxy or a flaky network) with backoff, up to `max_attempts` streams.
  // `options.timeout` bounds the whole.
  JobOutcome FollowJob(const std::string& job, int64_t from_event, const StreamOptions& options,
                       int max_attempts = 8);

  absl::StatusOr<v1::Job> SubmitJob(const v1::QuantizeRequest& request);
  absl::StatusOr<v1::Job> GetJob(const std::string& job, v1::JobView view = v1::FULL);
  absl::StatusOr<v1::ListJobsResponse> ListJobs(const v1::ListJobsRequest& request);
  absl::StatusOr<v1::Job> CancelJob(const std::string& job);

  absl::StatusOr<v1::Mesh> CreateMesh(const v1::TMesh& mesh);
  // CreateMesh for a mesh of any size: its binary form streamed in chunks of `chunk_bytes`
  // (UploadMesh), so that it is never one message above the server's limit.
  absl::StatusOr<v1::Mesh> UploadMesh(const v1::TMesh& mesh, int64_t chunk_bytes = 1 << 20);
  // If `request` carries a mesh larger than `above_bytes` (gRPC's default message limit), uploads
  // it and makes the request refer to it (stored_mesh); returns the stored mesh's name, which the
  // caller deletes once the job no longer needs it, or "" when nothing was uploaded.
  absl::StatusOr<std::string> UploadIfLarge(v1::QuantizeRequest& request,
                                            int64_t above_bytes = kUploadAboveBytes);
  static constexpr int64_t kUploadAboveBytes = 4 << 20;
  absl::StatusOr<v1::Mesh> GetMesh(const std::string& mesh);
  absl::Status DeleteMesh(const std::string& mesh);

  absl::StatusOr<v1::ServerStats> GetServerStats();

  const std::shared_ptr<grpc::Channel>& channel() const { return channel_; }

 private:
  void Prepare(grpc::ClientContext& context, absl::Duration timeout) const;
  // One unary call under `unary_timeout_`: every non-streaming method is this, with its stub
  // method.
  template <typename Request, typename Response>
  absl::StatusOr<Response> Unary(grpc::Status (v1::Quantizer::StubInterface::*method)(
                                     grpc::ClientContext*, const Request&, Response*),
                                 const Request& request) const {
    grpc::ClientContext context;
    Prepare(context, unary_timeout_);
    Response response;
    absl::Status status = StatusFromGrpc((stub_.get()->*method)(&context, request, &response));
    if (!status.ok()) return status;
    return response;
  }
  JobOutcome ReadStream(grpc::ClientContext& context,
                        grpc::ClientReaderInterface<v1::QuantizeEvent>& reader,
                        const EventHandler& on_event, JobOutcome outcome) const;

  std::shared_ptr<grpc::Channel> channel_;
  std::unique_ptr<v1::Quantizer::Stub> stub_;
  std::string auth_token_;
  absl::Duration unary_timeout_;
};

// Resource names accept the bare id for convenience on the command line: "abc" -> "jobs/abc".
std::string JobName(const std::string& name_or_id);

}  // namespace ispq::client

#endif  // ISPQ_CLIENT_QUANTIZER_CLIENT_H_
