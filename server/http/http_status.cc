// SPDX-License-Identifier: Apache-2.0
#include "server/http/http_status.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include "absl/strings/cord.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/time/time.h"
#include "google/protobuf/struct.pb.h"
#include "google/protobuf/util/json_util.h"
#include "server/jobs/retry_hint.h"

namespace ispq::server::http {
namespace {

constexpr char kHttpStatusPayload[] = "type.ispq.dev/ispq.server.HttpStatus";

}  // namespace

int HttpStatusCode(absl::StatusCode code) {
  switch (code) {
    case absl::StatusCode::kOk:
      return 200;
    case absl::StatusCode::kCancelled:
      return 499;
    case absl::StatusCode::kInvalidArgument:
    case absl::StatusCode::kFailedPrecondition:
    case absl::StatusCode::kOutOfRange:
      return 400;
    case absl::StatusCode::kUnauthenticated:
      return 401;
    case absl::StatusCode::kPermissionDenied:
      return 403;
    case absl::StatusCode::kNotFound:
      return 404;
    case absl::StatusCode::kAlreadyExists:
    case absl::StatusCode::kAborted:
      return 409;
    case absl::StatusCode::kResourceExhausted:
      return 429;
    case absl::StatusCode::kUnimplemented:
      return 501;
    case absl::StatusCode::kUnavailable:
      return 503;
    case absl::StatusCode::kDeadlineExceeded:
      return 504;
    case absl::StatusCode::kUnknown:
    case absl::StatusCode::kInternal:
    case absl::StatusCode::kDataLoss:
    default:
      return 500;
  }
}

absl::Status WithHttpStatus(absl::Status status, int http_status) {
  status.SetPayload(kHttpStatusPayload, absl::Cord(absl::StrCat(http_status)));
  return status;
}

int HttpStatusOf(const absl::Status& status) {
  const auto payload = status.GetPayload(kHttpStatusPayload);  // an absl::optional
  int http_status = 0;
  if (payload.has_value() && absl::SimpleAtoi(std::string(*payload), &http_status)) {
    return http_status;
  }
  return HttpStatusCode(status.code());
}

std::string ErrorJson(const absl::Status& status) {
  // Through protobuf's JSON printer, so that any message text is escaped correctly.
  google::protobuf::Struct body;
  auto& fields = *body.mutable_fields();
  fields["code"].set_number_value(static_cast<int>(status.code()));
  // absl::StatusCodeToString spells the canonical names as gRPC does ("INVALID_ARGUMENT").
  std::string name = absl::StatusCodeToString(status.code());
  fields["status"].set_string_value(name);
  fields["message"].set_string_value(std::string(status.message()));
  std::string json;
  if (!google::protobuf::util::MessageToJsonString(body, &json).ok()) {
    return absl::StrCat("{\"code\":", static_cast<int>(status.code()), "}");
  }
  return json;
}

std::optional<std::string> RetryAfterSeconds(const absl::Status& status) {
  const std::optional<absl::Duration> hint = RetryHintOf(status);
  if (!hint.has_value()) return std::nullopt;
  const double seconds = std::max(1.0, std::ceil(absl::ToDoubleSeconds(*hint)));
  return absl::StrCat(static_cast<int64_t>(seconds));
}

}  // namespace ispq::server::http
