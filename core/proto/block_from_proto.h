// SPDX-License-Identifier: Apache-2.0
// Decoding one block of an ispq.v1.TMesh message into a BlockInput (core/tmesh_input.h): its
// corners, edges and faces by their keys, its halfpatches, its arcs by direction and its nodes'
// block coordinates. Checks what belongs to the encoding (keys, arities, each key once, non-empty
// edges and faces, finite coordinates, ids in range) in the order the message lists them; the
// builder checks the rest. Part of TMeshFromProto (core/proto/tmesh_from_proto.h).
#ifndef ISPQ_CORE_PROTO_BLOCK_FROM_PROTO_H_
#define ISPQ_CORE_PROTO_BLOCK_FROM_PROTO_H_

#include "absl/status/statusor.h"
#include "core/proto/id_ranges.h"
#include "core/tmesh_input.h"
#include "ispq/v1/tmesh.pb.h"

namespace ispq {

// INVALID_ARGUMENT naming block b and what is malformed. The input's lists view `block`.
absl::StatusOr<BlockInput> BlockInputFromProto(BlockId b, const v1::Block& block,
                                               const IdRanges& ids);

}  // namespace ispq

#endif  // ISPQ_CORE_PROTO_BLOCK_FROM_PROTO_H_
