// SPDX-License-Identifier: Apache-2.0
#include "server/admission/raw_request.h"

namespace ispq::server {

absl::StatusOr<RawRequest> AccountRequest(std::unique_ptr<RequestBytes> bytes, int64_t max_bytes,
                                          MemoryAdmission& memory) {
  RawRequest raw;
  raw.size = bytes->size();
  raw.bytes = std::move(bytes);
  if (raw.size > max_bytes) {
    return absl::InvalidArgumentError(absl::StrCat(
        "the request is ", raw.size, " bytes; this method accepts at most ", max_bytes));
  }
  absl::StatusOr<MemoryReservation> accounted =
      memory.Account(MemoryUse::kRequests, raw.size, "the request");
  if (!accounted.ok()) return accounted.status();
  raw.memory = *std::move(accounted);
  return raw;
}

}  // namespace ispq::server
