// SPDX-License-Identifier: Apache-2.0
// One UploadMesh call: a mesh too large for one message, received as the chunks of its binary
// TMesh (proto/ispq/v1/service.proto) and then stored like a CreateMesh request.
//
// The first message declares the total size, which is checked against --max_upload_bytes and
// reserved in the memory budget before any chunk is kept. The chunks are kept as they arrive,
// never joined: behind a few bytes of CreateMeshRequest framing (server/admission/
// chunked_request_bytes.h) they are that request's bytes, which the job service then parses and
// validates off gRPC's threads like any CreateMesh (server/service/job_service.h). Fewer or more
// bytes than declared are INVALID_ARGUMENT. The UploadWatchdog cancels the call when no chunk
// comes for its idle limit; whatever ends the call releases the reservation.
//
// Created by QuantizerService::UploadMesh and returned to gRPC as the call's reactor; deletes
// itself when gRPC is done with the call. gRPC runs OnReadDone one read at a time; after the
// last read, only the service's answer touches the call.
#ifndef ISPQ_SERVER_GRPC_MESH_UPLOAD_H_
#define ISPQ_SERVER_GRPC_MESH_UPLOAD_H_

#include <cstdint>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "grpcpp/support/byte_buffer.h"
#include "grpcpp/support/server_callback.h"
#include "ispq/v1/service.pb.h"
#include "server/auth/principal.h"
#include "server/grpc/upload_watchdog.h"
#include "server/memory/memory_budget.h"
#include "server/service/job_service.h"

namespace ispq::server {

class MeshUpload final : public grpc::ServerReadReactor<grpc::ByteBuffer> {
 public:
  // Starts reading. `principal` is the authenticated caller. `service` and `watchdog` must
  // outlive the call.
  MeshUpload(grpc::CallbackServerContext* context, grpc::ByteBuffer* response, Principal principal,
             JobService& service, UploadWatchdog& watchdog, int64_t max_upload_bytes);

  void OnReadDone(bool ok) override;
  void OnDone() override;

 private:
  // The next message: the declaration or a chunk. Not OK ends the call.
  absl::Status Receive(v1::UploadMeshRequest& message);
  // All bytes are there: hand them to the service as a CreateMesh request.
  void Store();
  void Answer(const absl::StatusOr<v1::Mesh>& mesh);
  void Fail(const absl::Status& status);

  grpc::CallbackServerContext* const context_;
  grpc::ByteBuffer* const response_;
  Principal principal_;
  JobService& service_;
  UploadWatchdog& watchdog_;
  const int64_t max_upload_bytes_;

  grpc::ByteBuffer incoming_;
  int64_t declared_ = 0;  // 0 until the first message
  int64_t received_ = 0;
  std::vector<std::string> chunks_;  // the CreateMeshRequest framing first
  size_t prefix_size_ = 0;           // of that framing
  MemoryReservation memory_;
  MemoryReservation response_memory_;  // held until the response is sent
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_GRPC_MESH_UPLOAD_H_
