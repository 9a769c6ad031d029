// SPDX-License-Identifier: Apache-2.0
// Parsing requests and serializing responses of raw (ByteBuffer) callback methods.
//
// The service registers its methods raw so that it, not gRPC, decides what a request that is
// not a protobuf message gets: with typed callback methods gRPC 1.51 answers UNIMPLEMENTED with
// an empty message, which tells a client nothing. Here it is INVALID_ARGUMENT naming the
// message type that was expected.
#ifndef ISPQ_SERVER_RAW_PROTO_CALL_H_
#define ISPQ_SERVER_RAW_PROTO_CALL_H_

#include <string>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "absl/strings/str_cat.h"
#include "google/protobuf/message_lite.h"
#include "grpcpp/impl/codegen/proto_utils.h"
#include "grpcpp/support/byte_buffer.h"
#include "server/grpc/grpc_status.h"

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

}  // namespace ispq::server

#endif  // ISPQ_SERVER_RAW_PROTO_CALL_H_
