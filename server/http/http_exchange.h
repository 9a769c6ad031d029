// Request and response helpers shared by the HTTP routes: who the caller is (the same bearer
// tokens and principals as gRPC: `Authorization: Bearer <token>`, or `access_token=<token>` in
// the query for the browser's EventSource, which cannot set headers), and answers as protobuf
// JSON or as a mapped error (server/http/http_status.h). A JSON answer is accounted in the memory
// budget as a response until cpp-httplib has sent it, as gRPC answers are (server/unary_call.h).
#ifndef ISPQ_SERVER_HTTP_HTTP_EXCHANGE_H_
#define ISPQ_SERVER_HTTP_HTTP_EXCHANGE_H_

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "google/protobuf/message.h"
#include "httplib.h"
#include "server/authenticator.h"
#include "server/memory_admission.h"
#include "server/principal.h"

namespace ispq::server::http {

absl::StatusOr<Principal> AuthenticateRequest(const httplib::Request& request,
                                              const Authenticator& authenticator);

// Answers with `status` (not OK) as an error.
void ReplyError(httplib::Response& response, const absl::Status& status);

// Answers 200 with `message` in JSON, or RESOURCE_EXHAUSTED if the budget cannot hold it.
void ReplyJson(httplib::Response& response, const google::protobuf::Message& message,
               MemoryAdmission& memory);

// ReplyJson or ReplyError.
template <typename Message>
void Reply(httplib::Response& response, const absl::StatusOr<Message>& answer,
           MemoryAdmission& memory) {
  if (answer.ok()) {
    ReplyJson(response, *answer, memory);
  } else {
    ReplyError(response, answer.status());
  }
}

}  // namespace ispq::server::http

#endif  // ISPQ_SERVER_HTTP_HTTP_EXCHANGE_H_
