// SPDX-License-Identifier: Apache-2.0
#include "server/admission/chunked_request_bytes.h"

#include <numeric>
#include <utility>

#include "google/protobuf/io/coded_stream.h"
#include "google/protobuf/wire_format_lite.h"

namespace ispq::server {
namespace {

using google::protobuf::io::ZeroCopyInputStream;

int64_t TotalSize(const std::vector<std::string>& chunks) {
  return std::accumulate(chunks.begin(), chunks.end(), int64_t{0},
                         [](int64_t sum, const std::string& c) { return sum + c.size(); });
}

// The chunks one after the other (empty ones skipped).
class ChunkStream final : public ZeroCopyInputStream {
 public:
  explicit ChunkStream(const std::vector<std::string>& chunks) : chunks_(chunks) {}

  bool Next(const void** data, int* size) override {
    while (chunk_ < chunks_.size() && offset_ == chunks_[chunk_].size()) {
      ++chunk_;
      offset_ = 0;
    }
    if (chunk_ == chunks_.size()) return false;
    const std::string& chunk = chunks_[chunk_];
    *data = chunk.data() + offset_;
    *size = static_cast<int>(chunk.size() - offset_);
    position_ += *size;
    offset_ = chunk.size();
    return true;
  }
  void BackUp(int count) override {  // only into the chunk Next returned last
    offset_ -= count;
    position_ -= count;
  }
  bool Skip(int count) override {
    const void* data;
    int size;
    while (count > 0 && Next(&data, &size)) {
      if (size > count) {
        BackUp(size - count);
        return true;
      }
      count -= size;
    }
    return count == 0;
  }
  int64_t ByteCount() const override { return position_; }

 private:
  const std::vector<std::string>& chunks_;
  size_t chunk_ = 0;
  size_t offset_ = 0;
  int64_t position_ = 0;
};

}  // namespace

ChunkedRequestBytes::ChunkedRequestBytes(std::vector<std::string> chunks)
    : chunks_(std::move(chunks)), size_(TotalSize(chunks_)) {}

std::unique_ptr<ZeroCopyInputStream> ChunkedRequestBytes::Read() const {
  return std::make_unique<ChunkStream>(chunks_);
}

std::string CreateMeshRequestPrefix(int64_t mesh_bytes) {
  using google::protobuf::internal::WireFormatLite;
  std::string prefix;
  prefix.push_back(static_cast<char>(
      WireFormatLite::MakeTag(1, WireFormatLite::WIRETYPE_LENGTH_DELIMITED)));  // mesh = 1
  uint8_t varint[10];
  const uint8_t* end = google::protobuf::io::CodedOutputStream::WriteVarint64ToArray(
      static_cast<uint64_t>(mesh_bytes), varint);
  prefix.append(reinterpret_cast<const char*>(varint), end - varint);
  return prefix;
}

}  // namespace ispq::server
