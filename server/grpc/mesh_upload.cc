// SPDX-License-Identifier: Apache-2.0
#include "server/grpc/mesh_upload.h"

#include <memory>
#include <utility>

#include "absl/strings/str_cat.h"
#include "server/admission/chunked_request_bytes.h"
#include "server/admission/raw_request.h"
#include "server/grpc/byte_buffer_bytes.h"
#include "server/grpc/grpc_status.h"
#include "server/grpc/raw_proto_call.h"
#include "spdlog/spdlog.h"

namespace ispq::server {

MeshUpload::MeshUpload(grpc::CallbackServerContext* context, grpc::ByteBuffer* response,
                       Principal principal, JobService& service, UploadWatchdog& watchdog,
                       int64_t max_upload_bytes)
    : context_(context),
      response_(response),
      principal_(std::move(principal)),
      service_(service),
      watchdog_(watchdog),
      max_upload_bytes_(max_upload_bytes) {
  watchdog_.Watch(context_);
  StartRead(&incoming_);
}

void MeshUpload::OnReadDone(bool ok) {
  if (!ok) {
    // The client closed its side (all sent), or the call was cancelled (by the client, or by the
    // watchdog: the cancellation is then what the client sees).
    if (context_->IsCancelled()) {
      Fail(absl::CancelledError("the upload was cancelled"));
    } else if (declared_ == 0 || received_ != declared_) {
      Fail(absl::InvalidArgumentError(absl::StrCat("the upload ended after ", received_,
                                                   " bytes of the ", declared_,
                                                   " its first message declared (total_bytes)")));
    } else {
      Store();
    }
    return;
  }
  watchdog_.Touch(context_);
  ByteBufferBytes bytes(incoming_);
  absl::StatusOr<v1::UploadMeshRequest> message = ParseRequest<v1::UploadMeshRequest>(bytes);
  absl::Status received = message.ok() ? Receive(*message) : message.status();
  if (!received.ok()) {
    Fail(received);
    return;
  }
  StartRead(&incoming_);
}

absl::Status MeshUpload::Receive(v1::UploadMeshRequest& message) {
  if (declared_ == 0) {
    if (message.total_bytes() <= 0) {
      return absl::InvalidArgumentError(
          "the first message of an upload declares its size: total_bytes must be > 0");
    }
    if (message.total_bytes() > max_upload_bytes_) {
      return absl::InvalidArgumentError(absl::StrCat(
          "the upload of ", message.total_bytes(), " bytes is larger than the server accepts (",
          max_upload_bytes_, " bytes, --max_upload_bytes)"));
    }
    chunks_.push_back(CreateMeshRequestPrefix(message.total_bytes()));
    prefix_size_ = chunks_[0].size();
    absl::StatusOr<MemoryReservation> memory = service_.memory().Reserve(
        MemoryUse::kRequests, message.total_bytes() + chunks_[0].size(), "the upload");
    if (!memory.ok()) return memory.status();
    memory_ = *std::move(memory);
    declared_ = message.total_bytes();
  } else if (message.total_bytes() != 0 && message.total_bytes() != declared_) {
    return absl::InvalidArgumentError(absl::StrCat("total_bytes changed from ", declared_, " to ",
                                                   message.total_bytes(), " during the upload"));
  }
  received_ += static_cast<int64_t>(message.chunk().size());
  if (received_ > declared_) {
    return absl::InvalidArgumentError(absl::StrCat("the upload sent more than the ", declared_,
                                                   " bytes it declared (total_bytes)"));
  }
  if (!message.chunk().empty()) {
    chunks_.push_back(std::move(*message.mutable_chunk()));
  }
  return absl::OkStatus();
}

void MeshUpload::Store() {
  watchdog_.Forget(context_);  // parsing and storing are the service's, bounded by its own limits
  MeshCreation creation;
  creation.principal = principal_;
  creation.raw.size = declared_ + static_cast<int64_t>(prefix_size_);
  creation.raw.bytes = std::make_unique<ChunkedRequestBytes>(std::move(chunks_));
  creation.raw.memory = std::move(memory_);
  creation.mesh_offset = static_cast<int64_t>(prefix_size_);
  creation.abandoned = [context = context_] { return context->IsCancelled(); };
  creation.answer = [this](const absl::StatusOr<v1::Mesh>& mesh) { Answer(mesh); };
  service_.CreateMesh(std::move(creation));
}

void MeshUpload::Answer(const absl::StatusOr<v1::Mesh>& mesh) {
  if (!mesh.ok()) {
    Fail(mesh.status());
    return;
  }
  absl::StatusOr<MemoryReservation> memory = service_.memory().Account(
      MemoryUse::kResponses, static_cast<int64_t>(mesh->ByteSizeLong()), "the response");
  if (!memory.ok()) {
    Fail(memory.status());
    return;
  }
  response_memory_ = *std::move(memory);
  Finish(SerializeMessage(*mesh, *response_));
}

void MeshUpload::Fail(const absl::Status& status) {
  if (watchdog_.Forget(context_)) {
    spdlog::info("event=upload_dropped reason=idle idle_limit_ms={} received_bytes={}",
                 absl::ToInt64Milliseconds(watchdog_.idle_limit()), received_);
  }
  chunks_.clear();
  memory_.Release();
  Finish(ToGrpcStatus(status, *context_));
}

void MeshUpload::OnDone() {
  watchdog_.Forget(context_);
  delete this;
}

}  // namespace ispq::server
