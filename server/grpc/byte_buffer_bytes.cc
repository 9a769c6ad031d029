// SPDX-License-Identifier: Apache-2.0
#include "server/grpc/byte_buffer_bytes.h"

#include "grpcpp/support/proto_buffer_reader.h"

namespace ispq::server {
namespace {

// gRPC's reader over a buffer of its own, which shares the slices (the reader consumes it).
class SlicesStream final : public google::protobuf::io::ZeroCopyInputStream {
 public:
  explicit SlicesStream(const grpc::ByteBuffer& buffer) : shared_(buffer), reader_(&shared_) {}

  bool Next(const void** data, int* size) override { return reader_.Next(data, size); }
  void BackUp(int count) override { reader_.BackUp(count); }
  bool Skip(int count) override { return reader_.Skip(count); }
  int64_t ByteCount() const override { return reader_.ByteCount(); }

 private:
  grpc::ByteBuffer shared_;
  grpc::ProtoBufferReader reader_;
};

}  // namespace

ByteBufferBytes::ByteBufferBytes(grpc::ByteBuffer& buffer) { buffer_.Swap(&buffer); }

std::unique_ptr<google::protobuf::io::ZeroCopyInputStream> ByteBufferBytes::Read() const {
  return std::make_unique<SlicesStream>(buffer_);
}

}  // namespace ispq::server
