// SPDX-License-Identifier: Apache-2.0
// Serializing responses of raw (ByteBuffer) callback methods.
//
// The service registers its methods raw so that it, not gRPC, decides what a request that is
// not a protobuf message gets: with typed callback methods gRPC 1.51 answers UNIMPLEMENTED with
// an empty message, which tells a client nothing. Here it is INVALID_ARGUMENT naming the
// message type that was expected (requests are parsed by server/admission/raw_request.h).
#ifndef ISPQ_SERVER_GRPC_RAW_PROTO_CALL_H_
#define ISPQ_SERVER_GRPC_RAW_PROTO_CALL_H_

#include "google/protobuf/message_lite.h"
#include "grpcpp/impl/codegen/proto_utils.h"
#include "grpcpp/support/byte_buffer.h"

namespace ispq::server {

// Serializes `message` into `raw`, replacing its contents; INTERNAL if protobuf cannot.
grpc::Status SerializeMessage(const google::protobuf::MessageLite& message, grpc::ByteBuffer& raw);

}  // namespace ispq::server

#endif  // ISPQ_SERVER_GRPC_RAW_PROTO_CALL_H_
