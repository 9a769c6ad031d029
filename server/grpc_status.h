// The one place where the server's absl::Status becomes the grpc::Status a client sees. The
// canonical codes are the same numbers in both libraries.
#ifndef ISPQ_SERVER_GRPC_STATUS_H_
#define ISPQ_SERVER_GRPC_STATUS_H_

#include <string>

#include "absl/status/status.h"
#include "grpcpp/support/status.h"

namespace ispq::server {

inline grpc::Status ToGrpcStatus(const absl::Status& status) {
  if (status.ok()) return grpc::Status::OK;
  return grpc::Status(static_cast<grpc::StatusCode>(status.code()), std::string(status.message()));
}

}  // namespace ispq::server

#endif  // ISPQ_SERVER_GRPC_STATUS_H_
