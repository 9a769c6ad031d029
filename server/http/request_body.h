// SPDX-License-Identifier: Apache-2.0
// A request body as it arrives, held within its limit and the memory budget at every byte: a
// declared length is reserved in the budget whole before the first byte is read, a chunked body
// in growing steps as its bytes come, so that a body is refused at the byte that would pass
// --max_message_bytes or the budget instead of after it has been read (the reservation is what
// the string holds, its capacity). Not thread-safe: one request's event-thread calls.
#ifndef ISPQ_SERVER_HTTP_REQUEST_BODY_H_
#define ISPQ_SERVER_HTTP_REQUEST_BODY_H_

#include <cstdint>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/strings/string_view.h"
#include "server/admission/memory_admission.h"
#include "server/memory/memory_budget.h"

namespace ispq::server::http {

class RequestBody {
 public:
  // `memory` must outlive this object.
  RequestBody(MemoryAdmission& memory, int64_t max_bytes);

  // Reserves a declared length (at most max_bytes) before it is read; RESOURCE_EXHAUSTED when
  // the budget cannot hold it.
  absl::Status ExpectLength(int64_t length);
  // Appends what arrived: RESOURCE_EXHAUSTED with HTTP status 413 past max_bytes, or when the
  // budget cannot hold it. Nothing is kept after a refusal.
  absl::Status Append(absl::string_view bytes);

  int64_t size() const { return static_cast<int64_t>(bytes_.size()); }
  // The body and its reservations, taken out of this object.
  std::string TakeBytes() { return std::move(bytes_); }
  std::vector<MemoryReservation> TakeMemory() { return std::move(memory_); }

 private:
  // Makes room for `bytes` more, reserving it first.
  absl::Status Grow(int64_t bytes);

  MemoryAdmission& memory_admission_;
  const int64_t max_bytes_;
  std::string bytes_;
  std::vector<MemoryReservation> memory_;
  int64_t reserved_ = 0;
};

}  // namespace ispq::server::http

#endif  // ISPQ_SERVER_HTTP_REQUEST_BODY_H_
