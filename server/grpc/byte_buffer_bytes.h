// SPDX-License-Identifier: Apache-2.0
// A gRPC request's bytes as the server's RequestBytes (server/admission/request_bytes.h): read in
// place, over the slices gRPC received them in, so that a large request is never copied whole.
#ifndef ISPQ_SERVER_GRPC_BYTE_BUFFER_BYTES_H_
#define ISPQ_SERVER_GRPC_BYTE_BUFFER_BYTES_H_

#include <cstdint>
#include <memory>

#include "google/protobuf/io/zero_copy_stream.h"
#include "grpcpp/support/byte_buffer.h"
#include "server/admission/request_bytes.h"

namespace ispq::server {

class ByteBufferBytes final : public RequestBytes {
 public:
  // Takes `buffer`'s slices (it is left empty).
  explicit ByteBufferBytes(grpc::ByteBuffer& buffer);

  int64_t size() const override { return static_cast<int64_t>(buffer_.Length()); }
  std::unique_ptr<google::protobuf::io::ZeroCopyInputStream> Read() const override;

 private:
  grpc::ByteBuffer buffer_;
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_GRPC_BYTE_BUFFER_BYTES_H_
