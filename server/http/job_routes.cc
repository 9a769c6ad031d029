#include "server/http/job_routes.h"

#include <atomic>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "absl/base/thread_annotations.h"
#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "absl/synchronization/mutex.h"
#include "absl/time/time.h"
#include "grpcpp/support/byte_buffer.h"
#include "grpcpp/support/slice.h"
#include "server/http/http_exchange.h"
#include "server/http/proto_json.h"
#include "server/http/query_params.h"
#include "server/job_submission.h"
#include "server/resource_names.h"

namespace ispq::server::http {
namespace {

// How long a POST waits for its admission (parsing and validating a large mesh may wait for an
// admission thread); then it is DEADLINE_EXCEEDED, as a gRPC call past its deadline. Retry with
// the same request_id to learn what became of it.
constexpr absl::Duration kAdmissionTimeout = absl::Seconds(60);

std::string JobName(const httplib::Request& request) {
  return absl::StrCat(kJobCollection, "/", request.matches[1].str());
}

// The answer of an admission, which may come from another thread.
class PendingAnswer {
 public:
  void Set(const JobSubmission::Outcome& outcome) {
    absl::MutexLock lock(&mutex_);
    outcome_ = outcome;
  }
  std::optional<JobSubmission::Outcome> WaitUntil(absl::Time deadline) {
    absl::MutexLock lock(&mutex_);
    auto answered = [this]() ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_) { return outcome_.has_value(); };
    mutex_.AwaitWithDeadline(absl::Condition(&answered), deadline);
    return outcome_;
  }

 private:
  absl::Mutex mutex_;
  std::optional<JobSubmission::Outcome> outcome_ ABSL_GUARDED_BY(mutex_);
};

// The body, converted to the binary request and accounted in the budget as gRPC's bytes are.
// `body_memory` accounts for the JSON body itself, which cpp-httplib holds until the request ends.
absl::StatusOr<RawRequest> BinaryRequest(const std::string& body, const HttpParts& parts,
                                         const HttpLimits& limits, MemoryReservation& body_memory) {
  if (body.empty()) {
    return absl::InvalidArgumentError("the body is empty: send an ispq.v1.QuantizeRequest in JSON");
  }
  absl::StatusOr<MemoryReservation> accounted = parts.memory.Account(
      MemoryUse::kRequests, static_cast<int64_t>(body.size()), "the request body");
  if (!accounted.ok()) return accounted.status();
  body_memory = *std::move(accounted);
  absl::StatusOr<std::string> binary = JsonToBinary(*v1::QuantizeRequest::descriptor(), body);
  if (!binary.ok()) return binary.status();
  grpc::Slice slice(*binary);
  *binary = std::string();  // the slice holds the bytes now
  grpc::ByteBuffer buffer(&slice, 1);
  return TakeRequest(&buffer, limits.max_body_bytes, parts.memory);
}

void SubmitJob(const HttpParts& parts, const HttpLimits& limits, const httplib::Request& request,
               httplib::Response& response) {
  absl::StatusOr<Principal> principal = AuthenticateRequest(request, parts.authenticator);
  if (!principal.ok()) return ReplyError(response, principal.status());
  MemoryReservation body_memory;  // until the handler returns
  absl::StatusOr<RawRequest> raw = BinaryRequest(request.body, parts, limits, body_memory);
  if (!raw.ok()) {
    if (absl::IsInvalidArgument(raw.status())) parts.metrics.RecordRejectedInvalid();
    return ReplyError(response, raw.status());
  }
  auto pending = std::make_shared<PendingAnswer>();
  auto gave_up = std::make_shared<std::atomic<bool>>(false);
  JobSubmission submission;
  submission.principal = *std::move(principal);
  submission.raw = *std::move(raw);
  submission.peer = absl::StrCat("http:", request.remote_addr, ":", request.remote_port);
  submission.abandoned = [gave_up] { return gave_up->load(); };
  submission.answer = [pending](const JobSubmission::Outcome& job) { pending->Set(job); };
  parts.service.Submit(std::move(submission));
  const std::optional<JobSubmission::Outcome> job =
      pending->WaitUntil(absl::Now() + kAdmissionTimeout);
  if (!job.has_value()) {
    gave_up->store(true);
    return ReplyError(response, absl::DeadlineExceededError(absl::StrCat(
                                    "the request was not admitted within ",
                                    absl::FormatDuration(kAdmissionTimeout),
                                    "; retry with the same requestId to learn what became of it")));
  }
  if (!job->ok()) return ReplyError(response, job->status());
  ReplyJson(response, (**job)->ToProto(v1::FULL), parts.memory);
}

void GetJob(const HttpParts& parts, const httplib::Request& request, httplib::Response& response) {
  absl::StatusOr<Principal> principal = AuthenticateRequest(request, parts.authenticator);
  if (!principal.ok()) return ReplyError(response, principal.status());
  absl::StatusOr<v1::JobView> view = ViewParam(request);
  if (!view.ok()) return ReplyError(response, view.status());
  v1::GetJobRequest get;
  get.set_name(JobName(request));
  get.set_view(*view);
  Reply(response, parts.service.GetJob(get, *principal), parts.memory);
}

void ListJobs(const HttpParts& parts, const httplib::Request& request,
              httplib::Response& response) {
  absl::StatusOr<Principal> principal = AuthenticateRequest(request, parts.authenticator);
  if (!principal.ok()) return ReplyError(response, principal.status());
  v1::ListJobsRequest list;
  absl::StatusOr<int64_t> page_size =
      IntParam(request, "pageSize", 0, 0, std::numeric_limits<int32_t>::max());
  if (!page_size.ok()) return ReplyError(response, page_size.status());
  list.set_page_size(static_cast<int32_t>(*page_size));
  absl::StatusOr<v1::JobState> state = StateParam(request);
  if (!state.ok()) return ReplyError(response, state.status());
  list.set_state(*state);
  absl::StatusOr<v1::JobView> view = ViewParam(request);
  if (!view.ok()) return ReplyError(response, view.status());
  list.set_view(*view);
  list.set_page_token(request.get_param_value("pageToken"));
  Reply(response, parts.service.ListJobs(list, *principal), parts.memory);
}

void CancelJob(const HttpParts& parts, const httplib::Request& request,
               httplib::Response& response) {
  absl::StatusOr<Principal> principal = AuthenticateRequest(request, parts.authenticator);
  if (!principal.ok()) return ReplyError(response, principal.status());
  v1::CancelJobRequest cancel;
  cancel.set_name(JobName(request));
  Reply(response, parts.service.CancelJob(cancel, *principal), parts.memory);
}

}  // namespace

void AddJobRoutes(httplib::Server& server, const HttpParts& parts, const HttpLimits& limits) {
  server.Post("/v1/jobs",
              [&parts, limits](const httplib::Request& request, httplib::Response& response) {
                SubmitJob(parts, limits, request, response);
              });
  server.Get("/v1/jobs", [&parts](const httplib::Request& request, httplib::Response& response) {
    ListJobs(parts, request, response);
  });
  server.Get("/v1/jobs/([^/:]+)",
             [&parts](const httplib::Request& request, httplib::Response& response) {
               GetJob(parts, request, response);
             });
  server.Post("/v1/jobs/([^/:]+):cancel",
              [&parts](const httplib::Request& request, httplib::Response& response) {
                CancelJob(parts, request, response);
              });
}

}  // namespace ispq::server::http
