// SPDX-License-Identifier: Apache-2.0
// A retry hint carried by a RESOURCE_EXHAUSTED status from where it is decided (the job queue,
// the memory budget) to where it is sent (the service adds the `grpc-retry-pushback-ms` trailer
// of gRFC A6, which gRPC clients with a retry policy honour). The hint also appears in the
// message ("retry in N ms") for people and for clients without a retry policy.
#ifndef ISPQ_SERVER_JOBS_RETRY_HINT_H_
#define ISPQ_SERVER_JOBS_RETRY_HINT_H_

#include <optional>

#include "absl/status/status.h"
#include "absl/strings/string_view.h"
#include "absl/time/time.h"

namespace ispq::server {

// RESOURCE_EXHAUSTED with `message`, "; retry in N ms" appended and the hint attached.
absl::Status ResourceExhaustedWithRetryHint(absl::string_view message, absl::Duration hint);

// The hint attached to `status`, if any.
std::optional<absl::Duration> RetryHintOf(const absl::Status& status);

}  // namespace ispq::server

#endif  // ISPQ_SERVER_JOBS_RETRY_HINT_H_
