// SPDX-License-Identifier: Apache-2.0
#include "server/jobs/retry_hint.h"

#include <cstdint>
#include <string>

#include "absl/strings/cord.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"

namespace ispq::server {
namespace {

constexpr char kRetryHintPayload[] = "type.ispq.dev/ispq.server.RetryHintMs";

}  // namespace

absl::Status ResourceExhaustedWithRetryHint(absl::string_view message, absl::Duration hint) {
  const int64_t milliseconds = absl::ToInt64Milliseconds(hint);
  absl::Status status =
      absl::ResourceExhaustedError(absl::StrCat(message, "; retry in ", milliseconds, " ms"));
  status.SetPayload(kRetryHintPayload, absl::Cord(absl::StrCat(milliseconds)));
  return status;
}

std::optional<absl::Duration> RetryHintOf(const absl::Status& status) {
  const auto payload = status.GetPayload(kRetryHintPayload);  // an absl::optional
  int64_t milliseconds = 0;
  if (!payload.has_value() || !absl::SimpleAtoi(std::string(*payload), &milliseconds)) {
    return std::nullopt;
  }
  return absl::Milliseconds(milliseconds);
}

}  // namespace ispq::server
