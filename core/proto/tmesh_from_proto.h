// SPDX-License-Identifier: Apache-2.0
// Decoding an ispq.v1.TMesh message into the core TMesh model: the only way a mesh from a file
// or a request enters core/.
//
// The decoder checks what belongs to the encoding: the format version, list arities (3
// coordinates, 2 blocks and sides per patch, 8 corners, 12 edges, 6 faces, 4 patch sides, no
// empty block edge or face), direction, corner and edge keys (each once) and enum values, finite
// numbers the model does not keep, and above all that every id is in range, before anything is
// indexed by it. Blocks are decoded by core/proto/block_from_proto.h. It hands each element to
// TMeshBuilder (core/tmesh_builder.h), which checks every rule of the model and builds the mesh;
// then it checks the one rule about what the model does not keep: each interior patch's
// transition translation carries its nodes' coordinates in one block onto those in the other.
// A rejected mesh yields INVALID_ARGUMENT naming the offending element and the rule it breaks
// (e.g. "patch 12: ..."). Hostile input (ids of 2^31, NaN lengths, truncated lists) is rejected
// before anything is allocated from it.
#ifndef ISPQ_CORE_PROTO_TMESH_FROM_PROTO_H_
#define ISPQ_CORE_PROTO_TMESH_FROM_PROTO_H_

#include <functional>

#include "absl/status/statusor.h"
#include "core/tmesh.h"
#include "core/tmesh_builder.h"
#include "ispq/v1/tmesh.pb.h"

namespace ispq {

absl::StatusOr<TMesh> TMeshFromProto(const v1::TMesh& proto,
                                     const TMeshValidationOptions& options = {});

// The same for a mesh whose elements are not held in one message (core/proto/tmesh_from_wire.h
// reads them one at a time from the serialized bytes): `header_fields` carries every field but
// the four element lists, `sizes` their lengths, and `elements` hands the nodes, then the arcs,
// the patches and the blocks to the sink in id order (sizes.nodes nodes, and so on).
class TMeshElementSink {
 public:
  virtual ~TMeshElementSink() = default;
  virtual absl::Status Node(const v1::Node& node) = 0;
  virtual absl::Status Arc(const v1::Arc& arc) = 0;
  virtual absl::Status Patch(const v1::Patch& patch) = 0;
  virtual absl::Status Block(const v1::Block& block) = 0;
};
using TMeshElementSource = std::function<absl::Status(TMeshElementSink& sink)>;

absl::StatusOr<TMesh> TMeshFromParts(const v1::TMesh& header_fields, const TMeshSizes& sizes,
                                     const TMeshElementSource& elements,
                                     const TMeshValidationOptions& options = {});

}  // namespace ispq

#endif  // ISPQ_CORE_PROTO_TMESH_FROM_PROTO_H_
