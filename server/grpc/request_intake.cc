// SPDX-License-Identifier: Apache-2.0
#include "server/grpc/request_intake.h"

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"

namespace ispq::server {

absl::StatusOr<RawRequest> TakeRequest(const grpc::ByteBuffer* request, int64_t max_bytes,
                                       MemoryAdmission& memory) {
  RawRequest raw;
  // gRPC constructs the request object non-const in the call's arena and only destroys it.
  raw.bytes.Swap(const_cast<grpc::ByteBuffer*>(request));
  raw.size = static_cast<int64_t>(raw.bytes.Length());
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
