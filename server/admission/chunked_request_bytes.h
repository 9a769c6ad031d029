// SPDX-License-Identifier: Apache-2.0
// A request's bytes as a sequence of chunks, as a streamed upload (UploadMesh) delivers them,
// read in place as one stream: the chunks are never joined into one buffer, so a mesh larger
// than any single message costs its size once on the server, not twice.
#ifndef ISPQ_SERVER_ADMISSION_CHUNKED_REQUEST_BYTES_H_
#define ISPQ_SERVER_ADMISSION_CHUNKED_REQUEST_BYTES_H_

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "google/protobuf/io/zero_copy_stream.h"
#include "server/admission/request_bytes.h"

namespace ispq::server {

class ChunkedRequestBytes final : public RequestBytes {
 public:
  explicit ChunkedRequestBytes(std::vector<std::string> chunks);

  int64_t size() const override { return size_; }
  std::unique_ptr<google::protobuf::io::ZeroCopyInputStream> Read() const override;

 private:
  const std::vector<std::string> chunks_;
  const int64_t size_;
};

// The bytes that make the serialized `mesh_bytes` bytes of a TMesh into a serialized
// CreateMeshRequest when put in front of them (its field `mesh`: tag and length).
std::string CreateMeshRequestPrefix(int64_t mesh_bytes);

}  // namespace ispq::server

#endif  // ISPQ_SERVER_ADMISSION_CHUNKED_REQUEST_BYTES_H_
