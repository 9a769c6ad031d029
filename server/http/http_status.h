// SPDX-License-Identifier: Apache-2.0
// The one place where the server's absl::Status becomes what an HTTP client sees, as the
// google.api HTTP rules map gRPC codes (INVALID_ARGUMENT 400, UNAUTHENTICATED 401, NOT_FOUND
// 404, RESOURCE_EXHAUSTED 429, UNAVAILABLE 503...), with a google.rpc.Status-like JSON body
// {"code": <gRPC code number>, "status": "<gRPC code name>", "message": "..."} and, for a status
// with a retry hint (server/jobs/retry_hint.h), a Retry-After header in whole seconds. Refusals of
// the transport itself that gRPC has no code for (411, 413, 414, 415, 421, 431) carry their HTTP
// status with them (WithHttpStatus) and keep the same JSON body.
#ifndef ISPQ_SERVER_HTTP_HTTP_STATUS_H_
#define ISPQ_SERVER_HTTP_HTTP_STATUS_H_

#include <optional>
#include <string>

#include "absl/status/status.h"

namespace ispq::server::http {

// The HTTP status code for a gRPC code; CANCELLED is 499, as nginx and google.api have it.
int HttpStatusCode(absl::StatusCode code);

// `status` answered with `http_status` instead of its code's mapping.
absl::Status WithHttpStatus(absl::Status status, int http_status);
// The HTTP status `status` is answered with: the one attached by WithHttpStatus, else its code's.
int HttpStatusOf(const absl::Status& status);

// The JSON body of an error response.
std::string ErrorJson(const absl::Status& status);

// The Retry-After value (seconds, rounded up, at least 1) if `status` carries a retry hint.
std::optional<std::string> RetryAfterSeconds(const absl::Status& status);

}  // namespace ispq::server::http

#endif  // ISPQ_SERVER_HTTP_HTTP_STATUS_H_
