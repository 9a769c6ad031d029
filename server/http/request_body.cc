// SPDX-License-Identifier: Apache-2.0
#include "server/http/request_body.h"

#include <algorithm>
#include <utility>

#include "absl/status/statusor.h"
#include "absl/strings/str_cat.h"
#include "server/http/http_status.h"

namespace ispq::server::http {
namespace {

constexpr int kContentTooLarge = 413;
// The first step of a chunked body's reservation; later steps double what it has.
constexpr int64_t kFirstStep = 64 << 10;

}  // namespace

RequestBody::RequestBody(MemoryAdmission& memory, int64_t max_bytes)
    : memory_admission_(memory), max_bytes_(max_bytes) {}

absl::Status RequestBody::ExpectLength(int64_t length) {
  return Grow(std::min(length, max_bytes_) - reserved_);
}

absl::Status RequestBody::Append(absl::string_view bytes) {
  const int64_t needed = size() + static_cast<int64_t>(bytes.size());
  if (needed > max_bytes_) {
    bytes_ = std::string();
    memory_.clear();
    return WithHttpStatus(
        absl::ResourceExhaustedError(absl::StrCat("the body is larger than the ", max_bytes_,
                                                  " bytes this server accepts "
                                                  "(--max_message_bytes)")),
        kContentTooLarge);
  }
  if (needed > reserved_) {
    const int64_t step = std::max({needed, 2 * reserved_, kFirstStep});
    if (absl::Status grown = Grow(std::min(step, max_bytes_) - reserved_); !grown.ok()) {
      bytes_ = std::string();
      memory_.clear();
      return grown;
    }
  }
  bytes_.append(bytes.data(), bytes.size());
  return absl::OkStatus();
}

absl::Status RequestBody::Grow(int64_t bytes) {
  if (bytes <= 0) return absl::OkStatus();
  absl::StatusOr<MemoryReservation> reserved =
      memory_admission_.Reserve(MemoryUse::kRequests, bytes, "the request body");
  if (!reserved.ok()) return reserved.status();
  memory_.push_back(*std::move(reserved));
  reserved_ += bytes;
  bytes_.reserve(static_cast<size_t>(reserved_));
  return absl::OkStatus();
}

}  // namespace ispq::server::http
