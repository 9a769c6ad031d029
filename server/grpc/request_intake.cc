// SPDX-License-Identifier: Apache-2.0
#include "server/grpc/request_intake.h"

#include <memory>

#include "server/grpc/byte_buffer_bytes.h"

namespace ispq::server {

absl::StatusOr<RawRequest> TakeRequest(const grpc::ByteBuffer* request, int64_t max_bytes,
                                       MemoryAdmission& memory) {
  // gRPC constructs the request object non-const in the call's arena and only destroys it.
  return AccountRequest(std::make_unique<ByteBufferBytes>(*const_cast<grpc::ByteBuffer*>(request)),
                        max_bytes, memory);
}

}  // namespace ispq::server
