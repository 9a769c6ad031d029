// SPDX-License-Identifier: Apache-2.0
// How a request enters the server, within the memory budget: taken from its call, accounted as
// received, checked before parsing (server/admission/request_footprint.h), then parsed with its parsed size
// reserved. Every step that fails answers at once: INVALID_ARGUMENT for bytes that are no valid
// message or strings longer than accepted, RESOURCE_EXHAUSTED when the budget cannot hold it.
//
// The request is taken out of the call because gRPC would otherwise keep its bytes until the call
// ends, which for Quantize is when the job ends; the handler's request object is constructed and
// destroyed by gRPC and is ours to consume in between.
#ifndef ISPQ_SERVER_REQUEST_INTAKE_H_
#define ISPQ_SERVER_REQUEST_INTAKE_H_

#include <cstdint>
#include <string_view>
#include <utility>

#include "absl/status/statusor.h"
#include "grpcpp/support/byte_buffer.h"
#include "server/admission/memory_admission.h"
#include "server/admission/request_footprint.h"
#include "server/grpc/raw_proto_call.h"
#include "server/memory/memory_budget.h"

namespace ispq::server {

// The bytes of a request, with the memory accounted for them.
struct RawRequest {
  grpc::ByteBuffer bytes;
  int64_t size = 0;
  MemoryReservation memory;
};

// Takes the request's bytes out of its call and accounts for them. INVALID_ARGUMENT if they are
// more than `max_bytes` (a method whose requests are small), RESOURCE_EXHAUSTED if the budget
// cannot hold them even after eviction.
absl::StatusOr<RawRequest> TakeRequest(const grpc::ByteBuffer* request, int64_t max_bytes,
                                       MemoryAdmission& memory);

// A parsed request with the memory reserved for it.
template <typename Message>
struct ParsedRequest {
  Message message;
  MemoryReservation memory;
};

// Lets go of a request's bytes and their reservation.
inline void Discard(RawRequest& raw) {
  raw.bytes.Clear();
  raw.memory.Release();
}

// Reserves the parsed size, parses and lets go of the raw bytes, whether parsing succeeded or not:
// a refused request holds no memory once the caller hears why.
template <typename Message>
absl::StatusOr<ParsedRequest<Message>> ParseWithinBudget(RawRequest& raw, MemoryAdmission& memory) {
  absl::StatusOr<int64_t> estimate = EstimateParsedBytes(*Message::descriptor(), raw.bytes);
  if (!estimate.ok()) {
    Discard(raw);
    return estimate.status();
  }
  absl::StatusOr<MemoryReservation> reserved =
      memory.Reserve(MemoryUse::kRequests, *estimate, "parsing the request");
  if (!reserved.ok()) {
    Discard(raw);
    return reserved.status();
  }
  absl::StatusOr<Message> message = ParseRequest<Message>(raw.bytes);
  Discard(raw);
  if (!message.ok()) return message.status();
  return ParsedRequest<Message>{*std::move(message), *std::move(reserved)};
}

}  // namespace ispq::server

#endif  // ISPQ_SERVER_REQUEST_INTAKE_H_
