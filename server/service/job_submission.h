// SPDX-License-Identifier: Apache-2.0
// A SubmitJob (or Quantize) request as the service takes it from any transport (gRPC's
// SubmitJob and Quantize, the HTTP side's POST /v1/jobs, server/http/): who asks, the request's
// bytes within the memory budget, and how to answer. Both transports hand their requests to
// JobService::Submit (server/service/job_service.h), so validation, request ids, limits, memory
// accounting and errors are one code path.
#ifndef ISPQ_SERVER_SERVICE_JOB_SUBMISSION_H_
#define ISPQ_SERVER_SERVICE_JOB_SUBMISSION_H_

#include <functional>
#include <memory>
#include <string>

#include "absl/status/statusor.h"
#include "server/admission/raw_request.h"
#include "server/auth/principal.h"
#include "server/model/job.h"

namespace ispq::server {

struct JobSubmission {
  using Outcome = absl::StatusOr<std::shared_ptr<Job>>;

  Principal principal;
  RawRequest raw;    // a serialized ispq.v1.QuantizeRequest, accounted in the memory budget
  std::string peer;  // who sent it, for log lines
  // Whether the caller has gone away; admission then stops before parsing. Empty: never.
  std::function<bool()> abandoned;
  // Called exactly once with the job or the error, on whichever thread decided it (the caller's
  // own, an admission thread, or another call's with the same request id).
  std::function<void(const Outcome&)> answer;
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_SERVICE_JOB_SUBMISSION_H_
