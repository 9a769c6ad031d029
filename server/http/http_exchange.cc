#include "server/http/http_exchange.h"

#include <memory>
#include <string>
#include <utility>

#include "absl/strings/str_cat.h"
#include "server/http/http_status.h"
#include "server/http/proto_json.h"

namespace ispq::server::http {
namespace {

constexpr char kJsonType[] = "application/json";

}  // namespace

absl::StatusOr<Principal> AuthenticateRequest(const httplib::Request& request,
                                              const Authenticator& authenticator) {
  std::string authorization = request.get_header_value("Authorization");
  if (authorization.empty() && request.has_param("access_token")) {
    authorization = absl::StrCat("Bearer ", request.get_param_value("access_token"));
  }
  return authenticator.AuthenticateHttp(authorization);
}

void ReplyError(httplib::Response& response, const absl::Status& status) {
  response.status = HttpStatusCode(status.code());
  if (const std::optional<std::string> retry = RetryAfterSeconds(status); retry.has_value()) {
    response.set_header("Retry-After", *retry);
  }
  if (status.code() == absl::StatusCode::kUnauthenticated) {
    response.set_header("WWW-Authenticate", "Bearer");
  }
  response.set_content(ErrorJson(status), kJsonType);
}

void ReplyJson(httplib::Response& response, const google::protobuf::Message& message,
               MemoryAdmission& memory) {
  auto body = std::make_shared<std::string>(ToJson(message));
  absl::StatusOr<MemoryReservation> reserved =
      memory.Account(MemoryUse::kResponses, static_cast<int64_t>(body->size()), "the response");
  if (!reserved.ok()) {
    ReplyError(response, reserved.status());
    return;
  }
  auto held = std::make_shared<MemoryReservation>(*std::move(reserved));
  response.status = 200;
  // Served from `body` and released (with its reservation) once cpp-httplib is done with it.
  response.set_content_provider(
      body->size(), kJsonType,
      [body](size_t offset, size_t length, httplib::DataSink& sink) {
        return sink.write(body->data() + offset, length);
      },
      [body, held](bool /*success*/) mutable {
        held->Release();
        body.reset();
      });
}

}  // namespace ispq::server::http
