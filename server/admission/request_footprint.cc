// SPDX-License-Identifier: Apache-2.0
#include "server/admission/request_footprint.h"

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "google/protobuf/io/coded_stream.h"
#include "google/protobuf/message.h"
#include "google/protobuf/wire_format_lite.h"

namespace ispq::server {
namespace {

using google::protobuf::Descriptor;
using google::protobuf::FieldDescriptor;
using google::protobuf::internal::WireFormatLite;
using google::protobuf::io::CodedInputStream;

// glibc's per-allocation header and rounding.
constexpr int64_t kAllocationOverhead = 16;
// A repeated message or string: its pointer slot, doubled for the array's growth.
constexpr int64_t kRepeatedSlotBytes = 16;
// A heap std::string object behind a string field.
constexpr int64_t kStringObjectBytes = 32 + kAllocationOverhead;
// An unknown field: its entry in the UnknownFieldSet, with growth.
constexpr int64_t kUnknownFieldBytes = 64;
// protobuf's default recursion limit.
constexpr int kMaxDepth = 100;

int64_t ScalarBytes(const FieldDescriptor& field) {
  switch (field.cpp_type()) {
    case FieldDescriptor::CPPTYPE_INT64:
    case FieldDescriptor::CPPTYPE_UINT64:
    case FieldDescriptor::CPPTYPE_DOUBLE:
      return 8;
    case FieldDescriptor::CPPTYPE_BOOL:
      return 1;
    default:
      return 4;
  }
}

int64_t StringBytes(int64_t length) {
  // Beyond the small-string buffer the contents get their own block.
  return kStringObjectBytes + (length > 15 ? length + 1 + kAllocationOverhead : 0);
}

class FootprintWalk {
 public:
  FootprintWalk(const Descriptor& root, CodedInputStream& input, int max_string_bytes)
      : root_(root), input_(input), max_string_bytes_(max_string_bytes) {}

  // Walks one message up to the current limit, adding its estimated size to `bytes_`.
  absl::Status Message(const Descriptor& type, int depth) {
    if (depth > kMaxDepth) return Malformed();
    bytes_ += MessageBytes(type);
    while (const uint32_t tag = input_.ReadTag()) {
      const FieldDescriptor* field = type.FindFieldByNumber(WireFormatLite::GetTagFieldNumber(tag));
      absl::Status walked = field == nullptr ? Unknown(tag) : Field(*field, tag, depth);
      if (!walked.ok()) return walked;
    }
    // A zero tag ends the message only at its limit (or the end of the top-level buffer).
    if (!input_.ConsumedEntireMessage()) return Malformed();
    return absl::OkStatus();
  }

  int64_t bytes() const { return bytes_; }

 private:
  absl::Status Field(const FieldDescriptor& field, uint32_t tag, int depth) {
    const bool length_delimited =
        WireFormatLite::GetTagWireType(tag) == WireFormatLite::WIRETYPE_LENGTH_DELIMITED;
    const bool scalar = field.cpp_type() != FieldDescriptor::CPPTYPE_MESSAGE &&
                        field.cpp_type() != FieldDescriptor::CPPTYPE_STRING;
    // A wire type that does not fit the field makes protobuf keep it as an unknown field.
    if (length_delimited ? scalar && !field.is_repeated() : !scalar) return Unknown(tag);
    if (!length_delimited) {
      if (!WireFormatLite::SkipField(&input_, tag)) return Malformed();
      if (field.is_repeated()) bytes_ += 2 * ScalarBytes(field);
      return absl::OkStatus();
    }
    uint32_t length = 0;
    if (!input_.ReadVarint32(&length)) return Malformed();
    if (field.is_repeated()) bytes_ += kRepeatedSlotBytes;
    path_.push_back(&field);
    const CodedInputStream::Limit limit = input_.PushLimit(static_cast<int>(length));
    absl::Status walked = absl::OkStatus();
    if (field.type() == FieldDescriptor::TYPE_MESSAGE) {
      walked = Message(*field.message_type(), depth + 1);
    } else if (field.type() == FieldDescriptor::TYPE_STRING ||
               field.type() == FieldDescriptor::TYPE_BYTES) {
      walked = String(length);
    } else {
      walked = Packed(field);
    }
    input_.PopLimit(limit);
    path_.pop_back();
    return walked;
  }

  absl::Status String(uint32_t length) {
    if (length > static_cast<uint32_t>(max_string_bytes_)) {
      return absl::InvalidArgumentError(absl::StrCat(
          Path(), " is ", length, " bytes long; at most ", max_string_bytes_, " are accepted"));
    }
    if (!input_.Skip(static_cast<int>(length))) return Malformed();
    bytes_ += StringBytes(length);
    return absl::OkStatus();
  }

  // A packed repeated scalar field: counts its elements.
  absl::Status Packed(const FieldDescriptor& field) {
    int64_t count = 0;
    const int element = static_cast<int>(ScalarBytes(field));
    const bool fixed = field.type() == FieldDescriptor::TYPE_DOUBLE ||
                       field.type() == FieldDescriptor::TYPE_FLOAT ||
                       field.type() == FieldDescriptor::TYPE_FIXED32 ||
                       field.type() == FieldDescriptor::TYPE_FIXED64 ||
                       field.type() == FieldDescriptor::TYPE_SFIXED32 ||
                       field.type() == FieldDescriptor::TYPE_SFIXED64;
    if (fixed) {
      const int remaining = input_.BytesUntilLimit();
      count = remaining / element;
      if (!input_.Skip(remaining)) return Malformed();
    } else {
      uint64_t ignored = 0;
      while (input_.BytesUntilLimit() > 0) {
        if (!input_.ReadVarint64(&ignored)) return Malformed();
        ++count;
      }
    }
    bytes_ += 2 * count * element + kAllocationOverhead;
    return absl::OkStatus();
  }

  absl::Status Unknown(uint32_t tag) {
    const int before = input_.CurrentPosition();
    if (WireFormatLite::GetTagWireType(tag) == WireFormatLite::WIRETYPE_START_GROUP ||
        !WireFormatLite::SkipField(&input_, tag)) {
      return Malformed();
    }
    bytes_ += kUnknownFieldBytes + StringBytes(input_.CurrentPosition() - before);
    return absl::OkStatus();
  }

  // The class size of `type` plus its allocation, looked up once per type and walk.
  int64_t MessageBytes(const Descriptor& type) {
    for (const auto& [known, bytes] : message_bytes_) {
      if (known == &type) return bytes;
    }
    const google::protobuf::Message* prototype =
        google::protobuf::MessageFactory::generated_factory()->GetPrototype(&type);
    const int64_t bytes =
        (prototype != nullptr ? static_cast<int64_t>(prototype->SpaceUsedLong()) : 64) +
        kAllocationOverhead;
    message_bytes_.emplace_back(&type, bytes);
    return bytes;
  }

  std::string Path() const {
    std::string path;
    for (const FieldDescriptor* field : path_) {
      absl::StrAppend(&path, path.empty() ? "" : ".", field->name());
    }
    return path;
  }

  // The same words as a failed parse (server/admission/raw_request.h), for the top-level type.
  absl::Status Malformed() const {
    return absl::InvalidArgumentError(absl::StrCat("the request is not a valid ", root_.full_name(),
                                                   " message (binary protobuf)"));
  }

  const Descriptor& root_;
  CodedInputStream& input_;
  const int max_string_bytes_;
  int64_t bytes_ = 0;
  std::vector<const FieldDescriptor*> path_;
  std::vector<std::pair<const Descriptor*, int64_t>> message_bytes_;
};

}  // namespace

absl::StatusOr<int64_t> EstimateParsedBytes(const Descriptor& type, const RequestBytes& raw,
                                            int max_string_bytes) {
  const std::unique_ptr<google::protobuf::io::ZeroCopyInputStream> stream = raw.Read();
  CodedInputStream input(stream.get());
  input.SetTotalBytesLimit(INT32_MAX);
  FootprintWalk walk(type, input, max_string_bytes);
  if (absl::Status walked = walk.Message(type, 0); !walked.ok()) return walked;
  return walk.bytes();
}

}  // namespace ispq::server
