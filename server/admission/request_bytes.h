// SPDX-License-Identifier: Apache-2.0
// A request's serialized bytes as the server takes them from any transport: whatever holds them
// (gRPC's slices, server/grpc/byte_buffer_bytes.h; a string, for the HTTP side and tests) yields
// their size and a fresh stream over them, so that they are walked (server/admission/
// request_footprint.h) and parsed (server/admission/raw_request.h) where they lie, without a copy.
#ifndef ISPQ_SERVER_ADMISSION_REQUEST_BYTES_H_
#define ISPQ_SERVER_ADMISSION_REQUEST_BYTES_H_

#include <cstdint>
#include <memory>
#include <string>
#include <utility>

#include "google/protobuf/io/zero_copy_stream.h"

namespace ispq::server {

class RequestBytes {
 public:
  virtual ~RequestBytes() = default;

  // How many bytes there are.
  virtual int64_t size() const = 0;
  // A stream over all the bytes from the first; each call starts anew. Valid while this lives.
  virtual std::unique_ptr<google::protobuf::io::ZeroCopyInputStream> Read() const = 0;
};

// Bytes held in a string.
class StringRequestBytes final : public RequestBytes {
 public:
  explicit StringRequestBytes(std::string bytes) : bytes_(std::move(bytes)) {}

  int64_t size() const override { return static_cast<int64_t>(bytes_.size()); }
  std::unique_ptr<google::protobuf::io::ZeroCopyInputStream> Read() const override;

 private:
  const std::string bytes_;
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_ADMISSION_REQUEST_BYTES_H_
