// SPDX-License-Identifier: Apache-2.0
// Query parameters of the JSON API, parsed into the fields of the request messages they stand
// for; a malformed value is INVALID_ARGUMENT naming the parameter and what it accepts.
#ifndef ISPQ_SERVER_HTTP_QUERY_PARAMS_H_
#define ISPQ_SERVER_HTTP_QUERY_PARAMS_H_

#include <cstdint>

#include "absl/status/statusor.h"
#include "ispq/v1/service.pb.h"
#include "server/http/http_message.h"

namespace ispq::server::http {

// `name` as an integer in [minimum, maximum]; `fallback` when absent.
absl::StatusOr<int64_t> IntParam(const HttpRequest& request, const char* name, int64_t fallback,
                                 int64_t minimum, int64_t maximum);
// `view` (BASIC or FULL); unspecified when absent.
absl::StatusOr<v1::JobView> ViewParam(const HttpRequest& request);
// `state` (QUEUED, RUNNING, SUCCEEDED, FAILED or CANCELLED); unspecified when absent.
absl::StatusOr<v1::JobState> StateParam(const HttpRequest& request);

}  // namespace ispq::server::http

#endif  // ISPQ_SERVER_HTTP_QUERY_PARAMS_H_
