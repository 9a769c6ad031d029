// SPDX-License-Identifier: Apache-2.0
#include "server/http/http_exchange.h"

#include <optional>
#include <string>
#include <utility>

#include "absl/strings/str_cat.h"
#include "server/http/http_status.h"
#include "server/http/proto_json.h"

namespace ispq::server::http {
namespace {

constexpr char kJsonType[] = "application/json";

}  // namespace

absl::StatusOr<Principal> AuthenticateRequest(const HttpRequest& request,
                                              const Authenticator& authenticator) {
  std::string authorization(request.Header("authorization"));
  if (authorization.empty() && request.HasParam("access_token")) {
    authorization = absl::StrCat("Bearer ", request.Param("access_token"));
  }
  return authenticator.AuthenticateHttp(authorization);
}

HttpResponse ErrorResponse(const absl::Status& status) {
  HttpResponse response;
  response.status = HttpStatusOf(status);
  response.content_type = kJsonType;
  if (const std::optional<std::string> retry = RetryAfterSeconds(status); retry.has_value()) {
    response.headers.emplace_back("Retry-After", *retry);
  }
  if (status.code() == absl::StatusCode::kUnauthenticated) {
    response.headers.emplace_back("WWW-Authenticate", "Bearer");
  }
  response.body = ErrorJson(status);
  return response;
}

HttpResponse JsonResponse(const google::protobuf::Message& message, MemoryAdmission& memory) {
  std::string body = ToJson(message);
  absl::StatusOr<MemoryReservation> reserved =
      memory.Account(MemoryUse::kResponses, static_cast<int64_t>(body.size()), "the response");
  if (!reserved.ok()) return ErrorResponse(reserved.status());
  HttpResponse response;
  response.content_type = kJsonType;
  response.body = std::move(body);
  response.memory = *std::move(reserved);  // released once the body has been sent
  return response;
}

}  // namespace ispq::server::http
