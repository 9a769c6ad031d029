// SPDX-License-Identifier: Apache-2.0
#include "core/global_frame.h"

#include <utility>

namespace ispq {
namespace {

constexpr Dir kUnset = static_cast<Dir>(kNumDirs);

}  // namespace

std::optional<GlobalFrame> GlobalFrame::Compute(const TMesh& mesh) {
  if (mesh.num_blocks() == 0) return std::nullopt;
  GlobalFrame frame;
  std::vector<uint8_t> placed(mesh.num_blocks(), 0);
  frame.to_block_.assign(mesh.num_blocks(), Rotation());
  // Breadth-first across patches from block 0, as the search's charts cross them; a patch whose
  // rotation disagrees with the frames already given is a singular arc's (or a twisted part's).
  std::vector<BlockId> order = {0};
  placed[0] = 1;
  for (size_t i = 0; i < order.size(); ++i) {
    const BlockId b = order[i];
    for (const HalfpatchId side : mesh.block_halfpatches(b)) {
      if (mesh.halfpatch_block(side) != b) continue;
      const BlockId across = mesh.halfpatch_block(side ^ 1);
      if (across == kNoId) continue;
      const Rotation to_across = mesh.crossing_rotation(side).After(frame.to_block_[b]);
      if (placed[across] == 0) {
        placed[across] = 1;
        frame.to_block_[across] = to_across;
        order.push_back(across);
      } else if (!(frame.to_block_[across] == to_across)) {
        return std::nullopt;
      }
    }
  }
  if (static_cast<int>(order.size()) != mesh.num_blocks()) return std::nullopt;
  frame.arc_dir_.assign(mesh.num_arcs(), kUnset);
  for (BlockId b = 0; b < mesh.num_blocks(); ++b) {
    const Rotation to_global = frame.to_block_[b].Inverse();
    for (const BlockArc& entry : mesh.block_arcs(b)) {
      const Dir dir = to_global.Apply(entry.dir);
      Dir& known = frame.arc_dir_[entry.arc];
      if (known == kUnset) known = dir;
      if (known != dir) return std::nullopt;
    }
  }
  for (const Dir dir : frame.arc_dir_) {
    if (dir == kUnset) return std::nullopt;  // an arc on no block
  }
  return frame;
}

bool GlobalFrame::NodeCoordinates(const TMesh& mesh, std::span<const int64_t> q,
                                  std::vector<IntVec3>& coordinates) const {
  if (mesh.num_nodes() == 0) return true;
  coordinates.assign(mesh.num_nodes(), IntVec3{});
  std::vector<uint8_t> reached(mesh.num_nodes(), 0);
  std::vector<NodeId> order = {0};
  reached[0] = 1;
  for (size_t i = 0; i < order.size(); ++i) {
    const NodeId n = order[i];
    for (const HalfarcId h : mesh.outgoing_halfarcs(n)) {
      const NodeId m = mesh.head(h);
      if (reached[m] != 0) continue;
      const Dir dir = (h & 1) ? Opposite(arc_dir_[ArcOf(h)]) : arc_dir_[ArcOf(h)];
      coordinates[m] = AddAlong(coordinates[n], dir, q[ArcOf(h)]);
      reached[m] = 1;
      order.push_back(m);
    }
  }
  if (static_cast<int>(order.size()) != mesh.num_nodes()) return false;
  for (ArcId a = 0; a < mesh.num_arcs(); ++a) {
    const HalfarcId h = HalfarcOf(a, false);
    if (AddAlong(coordinates[mesh.tail(h)], arc_dir_[a], q[a]) != coordinates[mesh.head(h)]) {
      return false;  // a handle's period
    }
  }
  return true;
}

}  // namespace ispq
