// SPDX-License-Identifier: Apache-2.0
#include "server/http/job_routes.h"

#include <limits>
#include <memory>
#include <string>
#include <utility>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "absl/time/time.h"
#include "server/admission/raw_request.h"
#include "server/admission/request_bytes.h"
#include "server/http/http_exchange.h"
#include "server/http/json_guard.h"
#include "server/http/proto_json.h"
#include "server/http/query_params.h"
#include "server/http/request_framing.h"
#include "server/model/resource_names.h"
#include "server/service/job_submission.h"

namespace ispq::server::http {
namespace {

std::string JobName(const HttpRequest& request) {
  return absl::StrCat(kJobCollection, "/", request.id);
}

// The body, checked, converted to the binary request and accounted in the budget as gRPC's bytes
// are. While it is converted, the binary form and protobuf's work are reserved at the body's size
// (an estimate: the binary form of the API's JSON is usually smaller); the JSON body is let go as
// soon as it is converted. A binary body (application/x-protobuf: what a page sends for a
// `.tmesh.pb` file, whose bytes are the mesh field as they are) already is the request gRPC takes,
// and is handed on as it came; the parser checks it as it checks gRPC's.
absl::StatusOr<RawRequest> BinaryRequest(HttpRequest& request, const HttpParts& parts,
                                         const HttpLimits& limits) {
  if (request.body.empty()) {
    return absl::InvalidArgumentError(
        "the body is empty: send an ispq.v1.QuantizeRequest in JSON or binary protobuf");
  }
  if (IsProtobufBody(request)) {
    auto bytes = std::make_unique<StringRequestBytes>(std::move(request.body));
    request.ReleaseBody();  // the bytes moved on; AccountRequest accounts for them
    return AccountRequest(std::move(bytes), limits.max_body_bytes, parts.memory);
  }
  if (absl::Status checked = CheckJsonBody(request.body); !checked.ok()) return checked;
  absl::StatusOr<MemoryReservation> converted = parts.memory.Reserve(
      MemoryUse::kRequests, static_cast<int64_t>(request.body.size()), "converting the request");
  if (!converted.ok()) return converted.status();
  absl::StatusOr<std::string> binary =
      JsonToBinary(*v1::QuantizeRequest::descriptor(), request.body);
  request.ReleaseBody();
  if (!binary.ok()) return binary.status();
  auto bytes = std::make_unique<StringRequestBytes>(*std::move(binary));
  converted->Release();  // AccountRequest accounts for the bytes themselves
  return AccountRequest(std::move(bytes), limits.max_body_bytes, parts.memory);
}

void SubmitJob(const HttpParts& parts, const HttpLimits& limits, GeometryCache* geometry,
               HttpRequest& request, const std::shared_ptr<Responder>& responder) {
  absl::StatusOr<RawRequest> raw = BinaryRequest(request, parts, limits);
  if (!raw.ok()) {
    if (absl::IsInvalidArgument(raw.status())) parts.metrics.RecordRejectedInvalid();
    return responder->Answer(ErrorResponse(raw.status()));
  }
  JobSubmission submission;
  submission.principal = request.principal;
  submission.raw = *std::move(raw);
  submission.peer = absl::StrCat("http:", request.peer);
  submission.abandoned = [responder] { return responder->Answered(); };
  // On whichever thread decides; the answer is small (the new job, or the one a repeated
  // requestId names).
  submission.answer = [&parts, geometry, responder](const JobSubmission::Outcome& job) {
    if (!job.ok()) return responder->Answer(ErrorResponse(job.status()));
    // The page that submits a job draws it next; a small job may have ended by then.
    if (geometry != nullptr) geometry->Remember((*job)->name(), (*job)->mesh());
    responder->Answer(JsonResponse((*job)->ToProto(v1::FULL), parts.memory));
  };
  parts.service.Submit(std::move(submission));
}

void GetJob(const HttpParts& parts, HttpRequest& request,
            const std::shared_ptr<Responder>& responder) {
  absl::StatusOr<v1::JobView> view = ViewParam(request);
  if (!view.ok()) return responder->Answer(ErrorResponse(view.status()));
  v1::GetJobRequest get;
  get.set_name(JobName(request));
  get.set_view(*view);
  responder->Answer(Reply(parts.service.GetJob(get, request.principal), parts.memory));
}

absl::StatusOr<v1::ListJobsRequest> ListRequest(const HttpRequest& request) {
  v1::ListJobsRequest list;
  absl::StatusOr<int64_t> page_size =
      IntParam(request, "pageSize", 0, 0, std::numeric_limits<int32_t>::max());
  if (!page_size.ok()) return page_size.status();
  list.set_page_size(static_cast<int32_t>(*page_size));
  absl::StatusOr<v1::JobState> state = StateParam(request);
  if (!state.ok()) return state.status();
  list.set_state(*state);
  absl::StatusOr<v1::JobView> view = ViewParam(request);
  if (!view.ok()) return view.status();
  list.set_view(*view);
  list.set_page_token(std::string(request.Param("pageToken")));
  return list;
}

void ListJobs(const HttpParts& parts, HttpRequest& request,
              const std::shared_ptr<Responder>& responder) {
  absl::StatusOr<v1::ListJobsRequest> list = ListRequest(request);
  if (!list.ok()) return responder->Answer(ErrorResponse(list.status()));
  responder->Answer(Reply(parts.service.ListJobs(*list, request.principal), parts.memory));
}

void CancelJob(const HttpParts& parts, HttpRequest& request,
               const std::shared_ptr<Responder>& responder) {
  v1::CancelJobRequest cancel;
  cancel.set_name(JobName(request));
  responder->Answer(Reply(parts.service.CancelJob(cancel, request.principal), parts.memory));
}

// A route over jobs: authenticated, on the lookup threads.
Route JobRoute(const char* method, const char* pattern,
               void (*handle)(const HttpParts&, HttpRequest&, const std::shared_ptr<Responder>&),
               const HttpParts& parts) {
  Route route;
  route.method = method;
  route.pattern = pattern;
  route.lane = Lane::kLookup;
  route.authenticated = true;
  route.handle = [&parts, handle](HttpRequest& request,
                                  const std::shared_ptr<Responder>& responder) {
    handle(parts, request, responder);
  };
  return route;
}

}  // namespace

void AddJobRoutes(Router& router, const HttpParts& parts, const HttpLimits& limits,
                  GeometryCache* geometry) {
  Route submit = JobRoute("POST", "/v1/jobs", nullptr, parts);
  submit.lane = Lane::kParse;
  submit.takes_body = true;
  submit.takes_protobuf = true;
  submit.timeout_message = absl::StrCat(
      "the request was not admitted within ", absl::FormatDuration(limits.answer_timeout),
      "; retry with the same requestId to learn what became of it");
  submit.handle = [&parts, limits, geometry](HttpRequest& request,
                                             const std::shared_ptr<Responder>& responder) {
    SubmitJob(parts, limits, geometry, request, responder);
  };
  router.Add(std::move(submit));
  router.Add(JobRoute("GET", "/v1/jobs", &ListJobs, parts));
  router.Add(JobRoute("GET", "/v1/jobs/{id}", &GetJob, parts));
  router.Add(JobRoute("POST", "/v1/jobs/{id}:cancel", &CancelJob, parts));
}

}  // namespace ispq::server::http
