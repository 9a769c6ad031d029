// SPDX-License-Identifier: Apache-2.0
// How a gRPC request enters the server: its bytes taken from the call and accounted in the
// memory budget as received (server/admission/raw_request.h, which also parses them within the
// budget).
//
// The request is taken out of the call because gRPC would otherwise keep its bytes until the call
// ends, which for Quantize is when the job ends; the handler's request object is constructed and
// destroyed by gRPC and is ours to consume in between.
#ifndef ISPQ_SERVER_GRPC_REQUEST_INTAKE_H_
#define ISPQ_SERVER_GRPC_REQUEST_INTAKE_H_

#include <cstdint>

#include "absl/status/statusor.h"
#include "grpcpp/support/byte_buffer.h"
#include "server/admission/memory_admission.h"
#include "server/admission/raw_request.h"

namespace ispq::server {

// Takes the request's bytes out of its call and accounts for them. INVALID_ARGUMENT if they are
// more than `max_bytes` (a method whose requests are small), RESOURCE_EXHAUSTED if the budget
// cannot hold them even after eviction.
absl::StatusOr<RawRequest> TakeRequest(const grpc::ByteBuffer* request, int64_t max_bytes,
                                       MemoryAdmission& memory);

}  // namespace ispq::server

#endif  // ISPQ_SERVER_GRPC_REQUEST_INTAKE_H_
