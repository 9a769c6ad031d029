// SPDX-License-Identifier: Apache-2.0
#include "client/quantizer_client.h"

#include <algorithm>
#include <memory>
#include <string>
#include <utility>

#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "absl/time/clock.h"
#include "grpcpp/client_context.h"

namespace ispq::client {
namespace {

bool IsTransient(const absl::Status& status) {
  return absl::IsUnavailable(status) || absl::IsInternal(status) || absl::IsUnknown(status);
}

}  // namespace

absl::Status StatusFromGrpc(const grpc::Status& status) {
  if (status.ok()) return absl::OkStatus();
  return absl::Status(static_cast<absl::StatusCode>(status.error_code()), status.error_message());
}

std::string JobName(const std::string& name_or_id) {
  return absl::StartsWith(name_or_id, "jobs/") ? name_or_id : absl::StrCat("jobs/", name_or_id);
}

QuantizerClient::QuantizerClient(std::shared_ptr<grpc::Channel> channel, std::string auth_token,
                                 absl::Duration unary_timeout)
    : channel_(std::move(channel)),
      stub_(v1::Quantizer::NewStub(channel_)),
      auth_token_(std::move(auth_token)),
      unary_timeout_(unary_timeout) {}

absl::StatusOr<QuantizerClient> QuantizerClient::Connect(const ServerConnection& connection) {
  absl::StatusOr<std::shared_ptr<grpc::Channel>> channel = OpenChannel(connection);
  if (!channel.ok()) return channel.status();
  return QuantizerClient(*std::move(channel), connection.auth_token);
}

void QuantizerClient::Prepare(grpc::ClientContext& context, absl::Duration timeout) const {
  if (!auth_token_.empty()) context.AddMetadata("authorization", "Bearer " + auth_token_);
  if (timeout != absl::InfiniteDuration()) {
    context.set_deadline(absl::ToChronoTime(absl::Now() + timeout));
  }
}

JobOutcome QuantizerClient::ReadStream(grpc::ClientContext& context,
                                       grpc::ClientReaderInterface<v1::QuantizeEvent>& reader,
                                       const EventHandler& on_event, JobOutcome outcome) const {
  v1::QuantizeEvent event;
  bool stopped = false;
  while (reader.Read(&event)) {
    outcome.job = event.job();
    outcome.next_event = event.sequence() + 1;
    if (event.has_result()) {
      outcome.result = event.result();
      outcome.job_ended = true;
    } else if (event.has_error()) {
      outcome.status = absl::Status(static_cast<absl::StatusCode>(event.error().code()),
                                    event.error().message());
      outcome.job_ended = true;
    }
    if (on_event && !on_event(event)) {
      stopped = true;
      context.TryCancel();
      break;
    }
  }
  // Finish after a cancel needs the remaining messages drained.
  if (stopped) {
    while (reader.Read(&event)) {
    }
  }
  const absl::Status call_status = StatusFromGrpc(reader.Finish());
  if (outcome.job_ended) return outcome;  // the job's own outcome is what counts
  outcome.status =
      stopped ? absl::CancelledError("the event handler stopped the stream") : call_status;
  if (outcome.status.ok()) {
    // The server ends a stream successfully only after the terminal event, so the job ended
    // before the first event asked for.
    outcome.status =
        absl::OutOfRangeError(absl::StrCat("the job ended before event ", outcome.next_event,
                                           "; watch it from an earlier event to get its outcome"));
  }
  return outcome;
}

JobOutcome QuantizerClient::Quantize(const v1::QuantizeRequest& request,
                                     const StreamOptions& options) {
  grpc::ClientContext context;
  Prepare(context, options.timeout);
  std::unique_ptr<grpc::ClientReader<v1::QuantizeEvent>> reader =
      stub_->Quantize(&context, request);
  return ReadStream(context, *reader, options.on_event, JobOutcome{});
}

JobOutcome QuantizerClient::WatchJob(const std::string& job, int64_t from_event,
                                     const StreamOptions& options) {
  grpc::ClientContext context;
  Prepare(context, options.timeout);
  v1::WatchJobRequest request;
  request.set_name(job);
  request.set_from_event(from_event);
  std::unique_ptr<grpc::ClientReader<v1::QuantizeEvent>> reader =
      stub_->WatchJob(&context, request);
  JobOutcome outcome;
  outcome.job = job;
  outcome.next_event = from_event;
  return ReadStream(context, *reader, options.on_event, std::move(outcome));
}

JobOutcome QuantizerClient::FollowJob(const std::string& job, int64_t from_event,
                                      const StreamOptions& options, int max_attempts) {
  const absl::Time deadline = options.timeout == absl::InfiniteDuration()
                                  ? absl::InfiniteFuture()
                                  : absl::Now() + options.timeout;
  absl::Duration backoff = absl::Milliseconds(200);
  JobOutcome outcome;
  outcome.job = job;
  outcome.next_event = from_event;
  for (int attempt = 1;; ++attempt) {
    StreamOptions stream = options;
    stream.timeout = deadline - absl::Now();
    outcome = WatchJob(job, outcome.next_event, stream);
    if (outcome.job_ended || !IsTransient(outcome.status) || attempt >= max_attempts ||
        absl::Now() + backoff >= deadline) {
      return outcome;
    }
    absl::SleepFor(backoff);
    backoff = std::min(2 * backoff, absl::Seconds(10));
  }
}

absl::StatusOr<v1::Job> QuantizerClient::SubmitJob(const v1::QuantizeRequest& request) {
  return Unary(&v1::Quantizer::StubInterface::SubmitJob, request);
}

absl::StatusOr<v1::Job> QuantizerClient::GetJob(const std::string& job, v1::JobView view) {
  v1::GetJobRequest request;
  request.set_name(job);
  request.set_view(view);
  return Unary(&v1::Quantizer::StubInterface::GetJob, request);
}

absl::StatusOr<v1::ListJobsResponse> QuantizerClient::ListJobs(const v1::ListJobsRequest& request) {
  return Unary(&v1::Quantizer::StubInterface::ListJobs, request);
}

absl::StatusOr<v1::Job> QuantizerClient::CancelJob(const std::string& job) {
  v1::CancelJobRequest request;
  request.set_name(job);
  return Unary(&v1::Quantizer::StubInterface::CancelJob, request);
}

absl::StatusOr<v1::Mesh> QuantizerClient::UploadMesh(const v1::TMesh& mesh, int64_t chunk_bytes) {
  std::string bytes;
  if (!mesh.SerializeToString(&bytes)) {
    return absl::InvalidArgumentError("the mesh cannot be serialized (larger than 2 GiB?)");
  }
  grpc::ClientContext context;
  // A second per MiB on top of the unary timeout: slow links still finish, hung ones do not hang.
  Prepare(context, unary_timeout_ + absl::Seconds(static_cast<double>(bytes.size()) / (1 << 20)));
  v1::Mesh answer;
  std::unique_ptr<grpc::ClientWriterInterface<v1::UploadMeshRequest>> writer =
      stub_->UploadMesh(&context, &answer);
  v1::UploadMeshRequest message;
  message.set_total_bytes(static_cast<int64_t>(bytes.size()));
  size_t offset = 0;
  do {
    const size_t length = std::min(bytes.size() - offset, static_cast<size_t>(chunk_bytes));
    message.set_chunk(bytes.data() + offset, length);
    offset += length;
    if (!writer->Write(message)) break;  // the server ended the call: Finish says why
    message.clear_total_bytes();
  } while (offset < bytes.size());
  writer->WritesDone();
  const absl::Status status = StatusFromGrpc(writer->Finish());
  if (!status.ok()) return status;
  return answer;
}

absl::StatusOr<std::string> QuantizerClient::UploadIfLarge(v1::QuantizeRequest& request,
                                                           int64_t above_bytes) {
  if (!request.has_mesh() || static_cast<int64_t>(request.mesh().ByteSizeLong()) <= above_bytes) {
    return std::string();
  }
  absl::StatusOr<v1::Mesh> stored = UploadMesh(request.mesh());
  if (!stored.ok()) return stored.status();
  request.set_stored_mesh(stored->name());  // drops the mesh (one of mesh_source)
  return stored->name();
}

absl::StatusOr<v1::Mesh> QuantizerClient::CreateMesh(const v1::TMesh& mesh) {
  v1::CreateMeshRequest request;
  *request.mutable_mesh() = mesh;
  return Unary(&v1::Quantizer::StubInterface::CreateMesh, request);
}

absl::StatusOr<v1::Mesh> QuantizerClient::GetMesh(const std::string& mesh) {
  v1::GetMeshRequest request;
  request.set_name(mesh);
  return Unary(&v1::Quantizer::StubInterface::GetMesh, request);
}

absl::Status QuantizerClient::DeleteMesh(const std::string& mesh) {
  v1::DeleteMeshRequest request;
  request.set_name(mesh);
  return Unary(&v1::Quantizer::StubInterface::DeleteMesh, request).status();
}

absl::StatusOr<v1::ServerStats> QuantizerClient::GetServerStats() {
  return Unary(&v1::Quantizer::StubInterface::GetServerStats, v1::GetServerStatsRequest());
}

}  // namespace ispq::client
