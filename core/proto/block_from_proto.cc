// SPDX-License-Identifier: Apache-2.0
#include "core/proto/block_from_proto.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <optional>

#include "core/direction.h"
#include "core/invalid_argument.h"
#include "core/proto/repeated_field_span.h"
#include "core/status_macros.h"

namespace ispq {
namespace {

absl::Status DecodeCorners(BlockId b, const v1::Block& block, const IdRanges& ids,
                           BlockInput& input) {
  if (block.corners_size() != kNumCorners) {
    return InvalidArgument("block ", b, ": has ", block.corners_size(), " corners, not 8");
  }
  std::array<bool, kNumCorners> seen{};
  for (const v1::Corner& c : block.corners()) {
    const std::optional<int> code = CornerFromUpstreamBits(c.corner());
    const auto key = [&c] { return v1::UVWDir_Name(c.corner()); };  // for messages only
    if (!code) return InvalidArgument("block ", b, ": corner key ", key(), " is not a corner");
    if (seen[*code]) return InvalidArgument("block ", b, ": corner ", key(), " appears twice");
    if (!ids.Node(c.node())) {
      return InvalidArgument("block ", b, ": corner node ", c.node(), " does not exist");
    }
    seen[*code] = true;
    input.corners[*code] = c.node();
  }
  return absl::OkStatus();
}

absl::Status DecodeEdges(BlockId b, const v1::Block& block, const IdRanges& ids,
                         BlockInput& input) {
  if (block.edges_size() != kNumEdges) {
    return InvalidArgument("block ", b, ": has ", block.edges_size(), " edges, not 12");
  }
  std::array<bool, kNumEdges> seen{};
  int listed = 0;
  for (const v1::Edge& e : block.edges()) {
    const std::optional<int> code = EdgeFromUpstreamBits(e.edge());
    const auto key = [&e] { return v1::UVWDir_Name(e.edge()); };  // for messages only
    if (!code) return InvalidArgument("block ", b, ": edge key ", key(), " is not an edge");
    if (seen[*code]) return InvalidArgument("block ", b, ": edge ", key(), " appears twice");
    if (e.arcs_size() == 0) return InvalidArgument("block ", b, ": edge ", key(), " has no arcs");
    if (e.halfarcs_size() != e.arcs_size()) {
      return InvalidArgument("block ", b, ": edge ", key(), " lists ", e.arcs_size(), " arcs but ",
                             e.halfarcs_size(), " halfarcs");
    }
    for (int i = 0; i < e.arcs_size(); ++i) {
      if (!ids.Arc(e.arcs(i)) || !ids.Halfarc(e.halfarcs(i)) || ArcOf(e.halfarcs(i)) != e.arcs(i)) {
        return InvalidArgument("block ", b, ": edge ", key(), " arc ", e.arcs(i), " / halfarc ",
                               e.halfarcs(i), " is invalid");
      }
    }
    seen[*code] = true;
    input.edge_order[listed++] = static_cast<int8_t>(*code);
    input.edges[*code] = {View(e.arcs()), View(e.halfarcs())};
  }
  return absl::OkStatus();
}

// Faces list their patches, and the arcs and nodes strictly inside them, which the model does
// not keep but which must exist.
absl::Status DecodeFaces(BlockId b, const v1::Block& block, const IdRanges& ids,
                         BlockInput& input) {
  if (block.faces_size() != kNumDirs) {
    return InvalidArgument("block ", b, ": has ", block.faces_size(), " faces, not 6");
  }
  std::array<bool, kNumDirs> seen{};
  for (const v1::Face& f : block.faces()) {
    const std::optional<Dir> side = DirFromUpstreamBits(f.side());
    if (!side) {
      return InvalidArgument("block ", b, ": face key ", v1::UVWDir_Name(f.side()),
                             " is not a face side");
    }
    const char* name = DirName(*side);
    if (seen[DirIndex(*side)]) {
      return InvalidArgument("block ", b, ": face ", name, " appears twice");
    }
    if (f.patches_size() == 0) {
      return InvalidArgument("block ", b, ": face ", name, " has no patches");
    }
    for (int32_t p : f.patches()) {
      if (!ids.Patch(p)) {
        return InvalidArgument("block ", b, ": face ", name, " patch ", p, " does not exist");
      }
    }
    for (int32_t a : f.arcs()) {
      if (!ids.Arc(a)) {
        return InvalidArgument("block ", b, ": face ", name, " arc ", a, " does not exist");
      }
    }
    for (int32_t n : f.nodes()) {
      if (!ids.Node(n)) {
        return InvalidArgument("block ", b, ": face ", name, " node ", n, " does not exist");
      }
    }
    seen[DirIndex(*side)] = true;
    input.face_patches[DirIndex(*side)] = View(f.patches());
  }
  return absl::OkStatus();
}

absl::Status DecodeArcsByDir(BlockId b, const v1::Block& block, const IdRanges& ids,
                             BlockInput& input) {
  DirSet seen = 0;
  for (const v1::DirectedArcs& entry : block.arcs_by_dir()) {
    const std::optional<Dir> dir = DirFromUpstreamBits(entry.dir());
    if (!dir) {
      return InvalidArgument("block ", b, ": arcsByDir key ", v1::UVWDir_Name(entry.dir()),
                             " is not a direction");
    }
    if (seen & DirBit(*dir)) {
      return InvalidArgument("block ", b, ": arcsByDir lists ", DirName(*dir), " twice");
    }
    seen |= DirBit(*dir);
    for (int32_t a : entry.arcs()) {
      if (!ids.Arc(a)) {
        return InvalidArgument("block ", b, ": arcsByDir arc ", a, " does not exist");
      }
      input.arcs.push_back({a, *dir});
    }
  }
  return absl::OkStatus();
}

absl::Status DecodeNodeUvw(BlockId b, const v1::Block& block, const IdRanges& ids,
                           BlockInput& input) {
  for (const v1::NodeUvw& entry : block.node_uvw()) {
    const int32_t n = entry.node();
    if (!ids.Node(n)) return InvalidArgument("block ", b, ": nodeUvw node ", n, " does not exist");
    if (entry.uvw_size() != 3) {
      return InvalidArgument("block ", b, ": nodeUvw of node ", n, " needs 3 coordinates");
    }
    for (double x : entry.uvw()) {
      if (!std::isfinite(x)) {
        return InvalidArgument("block ", b, ": nodeUvw of node ", n, " is not finite");
      }
    }
    input.node_uvw.push_back({n, {entry.uvw(0), entry.uvw(1), entry.uvw(2)}});
  }
  return absl::OkStatus();
}

}  // namespace

absl::StatusOr<BlockInput> BlockInputFromProto(BlockId b, const v1::Block& block,
                                               const IdRanges& ids) {
  // The model has no self-adjacent blocks: a face glued to the same block elsewhere.
  if (block.self_adjacent()) {
    return InvalidArgument("block ", b, ": self-adjacent blocks are not supported");
  }
  BlockInput input;
  ISPQ_RETURN_IF_ERROR(DecodeCorners(b, block, ids, input));
  ISPQ_RETURN_IF_ERROR(DecodeEdges(b, block, ids, input));
  ISPQ_RETURN_IF_ERROR(DecodeFaces(b, block, ids, input));
  for (int32_t hp : block.halfpatches()) {
    if (!ids.Halfpatch(hp)) {
      return InvalidArgument("block ", b, ": halfpatch ", hp, " does not exist");
    }
  }
  input.halfpatches = View(block.halfpatches());
  ISPQ_RETURN_IF_ERROR(DecodeArcsByDir(b, block, ids, input));
  ISPQ_RETURN_IF_ERROR(DecodeNodeUvw(b, block, ids, input));
  return input;
}

}  // namespace ispq
