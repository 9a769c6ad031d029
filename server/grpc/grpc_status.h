// SPDX-License-Identifier: Apache-2.0
// The one place where the server's absl::Status becomes what a client sees: the grpc::Status
// (the canonical codes are the same numbers in both libraries) and, for a status with a retry
// hint (server/jobs/retry_hint.h), the `grpc-retry-pushback-ms` trailer of gRFC A6, which gRPC
// clients with a retry policy honour.
#ifndef ISPQ_SERVER_GRPC_GRPC_STATUS_H_
#define ISPQ_SERVER_GRPC_GRPC_STATUS_H_

#include <optional>
#include <string>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "absl/time/time.h"
#include "grpcpp/server_context.h"
#include "grpcpp/support/status.h"
#include "server/jobs/retry_hint.h"

namespace ispq::server {

inline grpc::Status ToGrpcStatus(const absl::Status& status) {
  if (status.ok()) return grpc::Status::OK;
  return grpc::Status(static_cast<grpc::StatusCode>(status.code()), std::string(status.message()));
}

// ToGrpcStatus, and the retry trailer on `context` if `status` carries a hint. Call before the
// call finishes.
inline grpc::Status ToGrpcStatus(const absl::Status& status, grpc::ServerContextBase& context) {
  if (const std::optional<absl::Duration> hint = RetryHintOf(status); hint.has_value()) {
    context.AddTrailingMetadata("grpc-retry-pushback-ms",
                                absl::StrCat(absl::ToInt64Milliseconds(*hint)));
  }
  return ToGrpcStatus(status);
}

}  // namespace ispq::server

#endif  // ISPQ_SERVER_GRPC_GRPC_STATUS_H_
