// SPDX-License-Identifier: Apache-2.0
// The standard gRPC health check (grpc.health.v1.Health/Check) from C++, for `ispq health`,
// container HEALTHCHECKs and tests.
//
// Debian ships no generated stubs for grpc.health.v1, so the call goes through a generic stub
// with well-known wrapper messages that have the same wire form: HealthCheckRequest is
// {string service = 1} like google.protobuf.StringValue, and HealthCheckResponse is
// {ServingStatus status = 1}, an enum (a varint) like google.protobuf.Int32Value.
#ifndef ISPQ_CLIENT_HEALTH_CHECK_H_
#define ISPQ_CLIENT_HEALTH_CHECK_H_

#include <memory>
#include <string>

#include "absl/status/statusor.h"
#include "absl/time/time.h"
#include "grpcpp/channel.h"

namespace ispq::client {

// grpc.health.v1.HealthCheckResponse.ServingStatus.
enum class ServingStatus { kUnknown = 0, kServing = 1, kNotServing = 2, kServiceUnknown = 3 };

const char* ServingStatusName(ServingStatus status);

// The status of `service` ("" is the whole server). The call's error if it fails (NOT_FOUND
// for a service the server does not know, UNAVAILABLE if nothing answers).
absl::StatusOr<ServingStatus> CheckHealth(const std::shared_ptr<grpc::Channel>& channel,
                                          const std::string& service, absl::Duration timeout);

}  // namespace ispq::client

#endif  // ISPQ_CLIENT_HEALTH_CHECK_H_
