// SPDX-License-Identifier: Apache-2.0
// How a request enters the server, within the memory budget, whichever transport brought it:
// accounted as received, checked before parsing (server/admission/request_footprint.h), then
// parsed with its parsed size reserved. Every step that fails answers at once: INVALID_ARGUMENT
// for bytes that are no valid message or strings longer than accepted, RESOURCE_EXHAUSTED when
// the budget cannot hold it. The transports take the bytes from their calls (gRPC's in
// server/grpc/request_intake.h, the HTTP side's in server/http/job_routes.cc).
#ifndef ISPQ_SERVER_ADMISSION_RAW_REQUEST_H_
#define ISPQ_SERVER_ADMISSION_RAW_REQUEST_H_

#include <cstdint>
#include <memory>
#include <utility>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "absl/strings/str_cat.h"
#include "server/admission/memory_admission.h"
#include "server/admission/request_bytes.h"
#include "server/admission/request_footprint.h"
#include "server/memory/memory_budget.h"

namespace ispq::server {

// The bytes of a request, with the memory accounted for them.
struct RawRequest {
  std::unique_ptr<RequestBytes> bytes;
  int64_t size = 0;
  MemoryReservation memory;
};

// Accounts for a request's bytes. INVALID_ARGUMENT if they are more than `max_bytes` (a method
// whose requests are small), RESOURCE_EXHAUSTED if the budget cannot hold them even after
// eviction.
absl::StatusOr<RawRequest> AccountRequest(std::unique_ptr<RequestBytes> bytes, int64_t max_bytes,
                                          MemoryAdmission& memory);

// A parsed request with the memory reserved for it.
template <typename Message>
struct ParsedRequest {
  Message message;
  MemoryReservation memory;
};

// Lets go of a request's bytes and their reservation.
inline void Discard(RawRequest& raw) {
  raw.bytes.reset();
  raw.memory.Release();
}

// `bytes` as a `Message`; INVALID_ARGUMENT naming the message type if they are none.
template <typename Message>
absl::StatusOr<Message> ParseRequest(const RequestBytes& bytes) {
  Message message;
  if (!message.ParseFromZeroCopyStream(bytes.Read().get())) {
    return absl::InvalidArgumentError(absl::StrCat("the request is not a valid ",
                                                   Message::descriptor()->full_name(),
                                                   " message (binary protobuf)"));
  }
  return message;
}

// Reserves the parsed size, parses and lets go of the raw bytes, whether parsing succeeded or not:
// a refused request holds no memory once the caller hears why.
template <typename Message>
absl::StatusOr<ParsedRequest<Message>> ParseWithinBudget(RawRequest& raw, MemoryAdmission& memory) {
  absl::StatusOr<int64_t> estimate = EstimateParsedBytes(*Message::descriptor(), *raw.bytes);
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
  absl::StatusOr<Message> message = ParseRequest<Message>(*raw.bytes);
  Discard(raw);
  if (!message.ok()) return message.status();
  return ParsedRequest<Message>{*std::move(message), *std::move(reserved)};
}

}  // namespace ispq::server

#endif  // ISPQ_SERVER_ADMISSION_RAW_REQUEST_H_
