// Parsing requests and serializing responses of raw (ByteBuffer) callback methods.
//
// The service registers its methods raw so that it, not gRPC, decides what a request that is
// not a protobuf message gets: with typed callback methods gRPC 1.51 answers UNIMPLEMENTED with
// an empty message, which tells a client nothing. Here it is INVALID_ARGUMENT naming the
// message type that was expected.
#ifndef ISPQ_SERVER_RAW_PROTO_CALL_H_
#define ISPQ_SERVER_RAW_PROTO_CALL_H_

#include <string>
#include <utility>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "absl/strings/str_cat.h"
#include "google/protobuf/message_lite.h"
#include "grpcpp/impl/codegen/proto_utils.h"
#include "grpcpp/server_context.h"
#include "grpcpp/support/byte_buffer.h"
#include "grpcpp/support/server_callback.h"
#include "server/grpc_status.h"

namespace ispq::server {

template <typename Message>
absl::StatusOr<Message> ParseRequest(const grpc::ByteBuffer& raw) {
  grpc::ByteBuffer buffer(raw);  // shares the slices; deserializing consumes the copy
  Message message;
  if (!grpc::SerializationTraits<Message>::Deserialize(&buffer, &message).ok()) {
    return absl::InvalidArgumentError(absl::StrCat("the request is not a valid ",
                                                   Message::descriptor()->full_name(),
                                                   " message (binary protobuf)"));
  }
  return message;
}

// Serializes `message` into `raw`, replacing its contents; INTERNAL if protobuf cannot.
grpc::Status SerializeMessage(const google::protobuf::MessageLite& message, grpc::ByteBuffer& raw);

// Answers a unary call: parses the request, runs `handler` (Request -> StatusOr<Response>) and
// finishes with its response or status.
template <typename Request, typename Handler>
grpc::ServerUnaryReactor* AnswerUnary(grpc::CallbackServerContext* context,
                                      const grpc::ByteBuffer& raw_request,
                                      grpc::ByteBuffer* raw_response, Handler&& handler) {
  grpc::ServerUnaryReactor* reactor = context->DefaultReactor();
  absl::StatusOr<Request> request = ParseRequest<Request>(raw_request);
  if (!request.ok()) {
    reactor->Finish(ToGrpcStatus(request.status()));
    return reactor;
  }
  auto response = std::forward<Handler>(handler)(*request);
  if (!response.ok()) {
    reactor->Finish(ToGrpcStatus(response.status()));
    return reactor;
  }
  reactor->Finish(SerializeMessage(*response, *raw_response));
  return reactor;
}

}  // namespace ispq::server

#endif  // ISPQ_SERVER_RAW_PROTO_CALL_H_
