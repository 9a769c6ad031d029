// SPDX-License-Identifier: Apache-2.0
#include "core/proto/tmesh_from_wire.h"

#include <cstdint>
#include <string>

#include "core/invalid_argument.h"
#include "core/proto/tmesh_from_proto.h"
#include "core/status_macros.h"
#include "google/protobuf/io/coded_stream.h"
#include "google/protobuf/io/zero_copy_stream_impl_lite.h"
#include "google/protobuf/wire_format_lite.h"
#include "ispq/v1/tmesh.pb.h"

namespace ispq {
namespace {

using google::protobuf::internal::WireFormatLite;
using google::protobuf::io::CodedInputStream;
using google::protobuf::io::CodedOutputStream;
using google::protobuf::io::StringOutputStream;

// The element lists' field numbers in ispq.v1.TMesh, in the order the decoder takes them.
constexpr int kNodes = v1::TMesh::kNodesFieldNumber;
constexpr int kArcs = v1::TMesh::kArcsFieldNumber;
constexpr int kPatches = v1::TMesh::kPatchesFieldNumber;
constexpr int kBlocks = v1::TMesh::kBlocksFieldNumber;
constexpr int64_t kMaxElements = (int64_t{1} << 30) - 1;  // proto/ispq/v1/tmesh.proto

// An entry of an element list. A field with one of their numbers but another wire type is an
// unknown field to protobuf's parser (and ignored), so it is to this decoder.
bool IsElement(uint32_t tag) {
  const int field = WireFormatLite::GetTagFieldNumber(tag);
  return field >= kNodes && field <= kBlocks &&
         WireFormatLite::GetTagWireType(tag) == WireFormatLite::WIRETYPE_LENGTH_DELIMITED;
}

// The next field's tag in `*tag`, 0 once the bytes end; false for a tag protobuf's parser
// refuses: a varint longer than the 5 bytes of a 32-bit one (CodedInputStream::ReadTag would keep
// its low bits and read another, valid-looking field there) or one naming field 0. Like the
// parser, a 5-byte tag keeps its low 32 bits.
bool ReadTag(CodedInputStream& input, uint32_t* tag) {
  const void* data = nullptr;
  int size = 0;
  if (!input.GetDirectBufferPointer(&data, &size)) {
    *tag = 0;
    return true;
  }
  uint64_t value = 0;
  const int start = input.CurrentPosition();
  if (!input.ReadVarint64(&value) || input.CurrentPosition() - start > 5 ||
      WireFormatLite::GetTagFieldNumber(static_cast<uint32_t>(value)) == 0) {
    return false;
  }
  *tag = static_cast<uint32_t>(value);
  return true;
}

absl::Status NotATMesh(const char* what) {
  return InvalidArgument("the bytes are not a binary T-mesh (ispq.v1.TMesh): ", what);
}

// The first pass: element counts, every other field (copied as they are into `header_fields`),
// and whether the element lists come one after the other in field order.
struct Scan {
  TMeshWireCounts counts;
  std::string header_fields;
  bool in_field_order = true;
};

absl::StatusOr<Scan> ScanFields(google::protobuf::io::ZeroCopyInputStream& bytes) {
  Scan scan;
  StringOutputStream header_stream(&scan.header_fields);
  {
    CodedInputStream input(&bytes);
    CodedOutputStream header(&header_stream);  // flushed into the string when it goes
    int last_element_field = 0;
    uint32_t tag = 0;
    while (true) {
      if (!ReadTag(input, &tag)) return NotATMesh("a field's tag is malformed");
      if (tag == 0) break;
      if (!IsElement(tag)) {
        if (!WireFormatLite::SkipField(&input, tag, &header)) {
          return NotATMesh("a field is cut off");
        }
        continue;
      }
      const int field = WireFormatLite::GetTagFieldNumber(tag);
      uint32_t length = 0;
      if (!input.ReadVarint32(&length) || !input.Skip(static_cast<int>(length))) {
        return NotATMesh("an element is cut off");
      }
      if (field < last_element_field) scan.in_field_order = false;
      last_element_field = field;
      int64_t& count = field == kNodes     ? scan.counts.nodes
                       : field == kArcs    ? scan.counts.arcs
                       : field == kPatches ? scan.counts.patches
                                           : scan.counts.blocks;
      if (++count > kMaxElements) {
        return InvalidArgument("a T-mesh has at most 2^30 - 1 of each element");
      }
    }
  }
  return scan;
}

// Parses the next `length` bytes of `input` into `message` (cleared first).
bool ParseElement(CodedInputStream& input, uint32_t length,
                  google::protobuf::MessageLite& message) {
  message.Clear();
  const CodedInputStream::Limit limit = input.PushLimit(static_cast<int>(length));
  const bool parsed = message.MergeFromCodedStream(&input) && input.ConsumedEntireMessage();
  input.PopLimit(limit);
  return parsed;
}

// The second pass: each element parsed into one reused message of its kind and handed on.
absl::Status HandOverElements(google::protobuf::io::ZeroCopyInputStream& bytes,
                              const TMeshWireHooks& hooks, TMeshElementSink& sink) {
  CodedInputStream input(&bytes);
  v1::Node node;
  v1::Arc arc;
  v1::Patch patch;
  v1::Block block;
  uint32_t tag = 0;
  while (true) {
    if (!ReadTag(input, &tag)) return NotATMesh("a field's tag is malformed");
    if (tag == 0) break;
    if (!IsElement(tag)) {
      if (!WireFormatLite::SkipField(&input, tag)) return NotATMesh("a field is cut off");
      continue;
    }
    const int field = WireFormatLite::GetTagFieldNumber(tag);
    uint32_t length = 0;
    if (!input.ReadVarint32(&length)) return NotATMesh("an element is cut off");
    const auto parsed = [&](google::protobuf::MessageLite& message) {
      return ParseElement(input, length, message) ? absl::OkStatus()
                                                  : NotATMesh("an element is no valid message");
    };
    switch (field) {
      case kNodes:
        ISPQ_RETURN_IF_ERROR(parsed(node));
        if (hooks.on_node) hooks.on_node(node);
        ISPQ_RETURN_IF_ERROR(sink.Node(node));
        break;
      case kArcs:
        ISPQ_RETURN_IF_ERROR(parsed(arc));
        ISPQ_RETURN_IF_ERROR(sink.Arc(arc));
        break;
      case kPatches:
        ISPQ_RETURN_IF_ERROR(parsed(patch));
        ISPQ_RETURN_IF_ERROR(sink.Patch(patch));
        break;
      default:
        ISPQ_RETURN_IF_ERROR(parsed(block));
        ISPQ_RETURN_IF_ERROR(sink.Block(block));
    }
  }
  return absl::OkStatus();
}

}  // namespace

absl::StatusOr<TMesh> TMeshFromWire(const TMeshBytesReader& read, const TMeshWireHooks& hooks,
                                    const TMeshValidationOptions& options) {
  absl::StatusOr<Scan> scan = ScanFields(*read());
  if (!scan.ok()) return scan.status();
  if (hooks.check_counts) ISPQ_RETURN_IF_ERROR(hooks.check_counts(scan->counts));
  if (!scan->in_field_order) {
    v1::TMesh whole;
    if (!whole.ParseFromZeroCopyStream(read().get())) return NotATMesh("it does not parse");
    absl::StatusOr<TMesh> mesh = TMeshFromProto(whole, options);
    if (mesh.ok() && hooks.on_node) {
      for (const v1::Node& node : whole.nodes()) hooks.on_node(node);
    }
    return mesh;
  }
  v1::TMesh header_fields;
  if (!header_fields.ParseFromString(scan->header_fields)) {
    return NotATMesh("a field outside the element lists does not parse");
  }
  scan->header_fields = std::string();  // the critical entities may be large
  const TMeshSizes sizes{static_cast<int>(scan->counts.nodes), static_cast<int>(scan->counts.arcs),
                         static_cast<int>(scan->counts.patches),
                         static_cast<int>(scan->counts.blocks)};
  return TMeshFromParts(
      header_fields, sizes,
      [&](TMeshElementSink& sink) { return HandOverElements(*read(), hooks, sink); }, options);
}

}  // namespace ispq
