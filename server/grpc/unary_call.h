// SPDX-License-Identifier: Apache-2.0
// A unary call answered from whichever thread has the answer (gRPC's own for lookups, an
// admission thread for requests that carry meshes), with its response accounted in the memory
// budget until gRPC has sent it: a job with its result or a page of jobs can be megabytes, and
// many clients asking at once would otherwise hold gigabytes beyond the budget's view.
//
// Created by a method handler and returned to gRPC as the call's reactor; deletes itself when
// gRPC is done with the call. Exactly one of Fail and Answer must be called, once.
#ifndef ISPQ_SERVER_GRPC_UNARY_CALL_H_
#define ISPQ_SERVER_GRPC_UNARY_CALL_H_

#include "absl/status/status.h"
#include "google/protobuf/message_lite.h"
#include "grpcpp/support/byte_buffer.h"
#include "grpcpp/support/server_callback.h"
#include "server/admission/memory_admission.h"
#include "server/memory/memory_budget.h"

namespace ispq::server {

class UnaryCall final : public grpc::ServerUnaryReactor {
 public:
  // `context` and `response` are the call's; `memory` must outlive the call.
  UnaryCall(grpc::CallbackServerContext* context, grpc::ByteBuffer* response,
            MemoryAdmission* memory);

  grpc::CallbackServerContext& context() { return *context_; }

  // Ends the call with `status` (not OK), with its retry trailer if it has a hint.
  void Fail(const absl::Status& status);
  // Ends the call with `message`, or RESOURCE_EXHAUSTED if the budget cannot hold it.
  void Answer(const google::protobuf::MessageLite& message);

  void OnDone() override { delete this; }

 private:
  grpc::CallbackServerContext* const context_;
  grpc::ByteBuffer* const response_;
  MemoryAdmission* const memory_;
  MemoryReservation response_memory_;  // held until the response is sent
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_GRPC_UNARY_CALL_H_
