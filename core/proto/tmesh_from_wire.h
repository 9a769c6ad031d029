// SPDX-License-Identifier: Apache-2.0
// Decoding a serialized ispq.v1.TMesh into the core TMesh model without ever holding the parsed
// message: the elements are parsed one at a time into one reused message each and handed to the
// decoder of core/proto/tmesh_from_proto.h, with the same checks and errors.
//
// A parsed message costs several times its serialized size (a sub-message object per node, arc,
// patch and block): a million-arc part of 264 MB took 1.8 GB of server memory parsed, five times
// the 316 MB of the TMesh built from it. Read this way, the bytes and the model are all there is.
//
// The bytes are read twice: a first pass counts the elements (the decoder checks every id against
// the counts before anything is indexed by it) and keeps every other field, a second one decodes
// the elements. Serializers write the four element lists in field order; bytes that interleave
// them (legal protobuf, written by no serializer) are parsed whole as a message instead.
#ifndef ISPQ_CORE_PROTO_TMESH_FROM_WIRE_H_
#define ISPQ_CORE_PROTO_TMESH_FROM_WIRE_H_

#include <functional>
#include <memory>

#include "absl/status/statusor.h"
#include "core/tmesh.h"
#include "core/tmesh_builder.h"
#include "google/protobuf/io/zero_copy_stream.h"
#include "ispq/v1/tmesh.pb.h"

namespace ispq {

// A fresh stream over the serialized TMesh from its first byte, each time it is called.
using TMeshBytesReader =
    std::function<std::unique_ptr<google::protobuf::io::ZeroCopyInputStream>()>;

// What the first pass found: the element counts.
struct TMeshWireCounts {
  int64_t nodes = 0, arcs = 0, patches = 0, blocks = 0;
};

// What a caller may do along the way, both optional: bound the counts before the mesh is built
// (an error ends the decoding with it), and see each node's message as it is decoded, in id
// order, for what the model leaves out (its position).
struct TMeshWireHooks {
  std::function<absl::Status(const TMeshWireCounts&)> check_counts = {};
  std::function<void(const v1::Node&)> on_node = {};
};

// INVALID_ARGUMENT for bytes that are no TMesh message (naming what is wrong), or whatever the
// decoder says of the mesh (naming the element).
absl::StatusOr<TMesh> TMeshFromWire(const TMeshBytesReader& read, const TMeshWireHooks& hooks = {},
                                    const TMeshValidationOptions& options = {});

}  // namespace ispq

#endif  // ISPQ_CORE_PROTO_TMESH_FROM_WIRE_H_
