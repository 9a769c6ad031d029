// SPDX-License-Identifier: Apache-2.0
// Request and response helpers shared by the HTTP routes: who the caller is (the same bearer
// tokens and principals as gRPC: `Authorization: Bearer <token>`, or `access_token=<token>` in
// the query for the browser's EventSource, which cannot set headers), and answers as protobuf
// JSON or as a mapped error (server/http/http_status.h). A JSON answer is accounted in the memory
// budget as a response until it has been sent, as gRPC answers are (server/grpc/unary_call.h).
#ifndef ISPQ_SERVER_HTTP_HTTP_EXCHANGE_H_
#define ISPQ_SERVER_HTTP_HTTP_EXCHANGE_H_

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "google/protobuf/message.h"
#include "server/admission/memory_admission.h"
#include "server/auth/authenticator.h"
#include "server/auth/principal.h"
#include "server/http/http_message.h"

namespace ispq::server::http {

absl::StatusOr<Principal> AuthenticateRequest(const HttpRequest& request,
                                              const Authenticator& authenticator);

// The answer to `status` (not OK): the mapped HTTP status, the JSON error body, Retry-After for a
// retry hint and WWW-Authenticate for UNAUTHENTICATED.
HttpResponse ErrorResponse(const absl::Status& status);

// 200 with `message` in JSON, or RESOURCE_EXHAUSTED if the budget cannot hold it.
HttpResponse JsonResponse(const google::protobuf::Message& message, MemoryAdmission& memory);

// JsonResponse or ErrorResponse.
template <typename Message>
HttpResponse Reply(const absl::StatusOr<Message>& answer, MemoryAdmission& memory) {
  if (answer.ok()) return JsonResponse(*answer, memory);
  return ErrorResponse(answer.status());
}

}  // namespace ispq::server::http

#endif  // ISPQ_SERVER_HTTP_HTTP_EXCHANGE_H_
