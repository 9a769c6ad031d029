// SPDX-License-Identifier: Apache-2.0
#include "server/grpc/unary_call.h"

#include <utility>

#include "server/grpc/grpc_status.h"
#include "server/grpc/raw_proto_call.h"

namespace ispq::server {

UnaryCall::UnaryCall(grpc::CallbackServerContext* context, grpc::ByteBuffer* response,
                     MemoryAdmission* memory)
    : context_(context), response_(response), memory_(memory) {}

void UnaryCall::Fail(const absl::Status& status) { Finish(ToGrpcStatus(status, *context_)); }

void UnaryCall::Answer(const google::protobuf::MessageLite& message) {
  // The serialized copy is what lingers until a slow client has read it.
  absl::StatusOr<MemoryReservation> memory = memory_->Account(
      MemoryUse::kResponses, static_cast<int64_t>(message.ByteSizeLong()), "the response");
  if (!memory.ok()) {
    Fail(memory.status());
    return;
  }
  response_memory_ = *std::move(memory);
  Finish(SerializeMessage(message, *response_));
}

}  // namespace ispq::server
