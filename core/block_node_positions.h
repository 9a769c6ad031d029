// SPDX-License-Identifier: Apache-2.0
// Integer positions of the nodes on every block's boundary (core/README.md, section Integer
// positions).
//
// For a consistent integer quantization q, every node n on the boundary of block b has a
// well-defined position P_b(n) in b's frame, with b's (-,-,-) corner at the origin: the sum of
// q along any chain of b's boundary arcs from that corner. The separation search needs these
// positions constantly (block boxes, patch boxes), so each (block, boundary node) pair gets a
// dense "slot" index once per mesh, and a call fills one position per slot by walking a
// precomputed spanning tree of each block's boundary: O(sum of block boundary sizes), no search.
#ifndef ISPQ_CORE_BLOCK_NODE_POSITIONS_H_
#define ISPQ_CORE_BLOCK_NODE_POSITIONS_H_

#include <cstdint>
#include <span>
#include <vector>

#include "core/integer_box.h"
#include "core/tmesh.h"

namespace ispq {

using SlotId = int32_t;

class BlockNodeSlots {
 public:
  explicit BlockNodeSlots(const TMesh& mesh);

  int num_slots() const { return static_cast<int>(slot_node_.size()); }
  BlockId block_of(SlotId s) const { return slot_block_[s]; }
  // The slots of block b are first_slot(b) .. end_slot(b) - 1, ascending by node id.
  SlotId first_slot(BlockId b) const { return block_first_slot_[b]; }
  SlotId end_slot(BlockId b) const { return block_first_slot_[b + 1]; }
  NodeId node_of(SlotId s) const { return slot_node_[s]; }
  // Slot of node n on block b, or kNoId if n is not on b's boundary (binary search).
  SlotId Find(BlockId b, NodeId n) const;
  // Slot of the corner with the given corner code (core/direction.h) of block b.
  SlotId corner_slot(BlockId b, int corner) const { return corner_slots_[b][corner]; }

  // positions[s] = P_b(n) for slot s = (b, n). positions.size() must be num_slots(). When q is
  // not consistent the result depends on the spanning tree and means nothing.
  void ComputePositions(std::span<const int64_t> q, std::span<IntVec3> positions) const;
  // The same for the slots of block b only (the others are left as they are): for searches that
  // read the positions of a few blocks.
  void ComputeBlockPositions(BlockId b, std::span<const int64_t> q,
                             std::span<IntVec3> positions) const;
  // Whether block b's positions read an arc with marked_arcs[arc] != 0. If the marked arcs are
  // those two q's differ on, b's positions are the same on both q's when this is false (for
  // searches that remember what an earlier q led to).
  bool PositionsDependOn(BlockId b, std::span<const uint8_t> marked_arcs) const;

 private:
  // One edge of a block's spanning tree: P[slot] = P[parent] + q[arc] * direction.
  struct TreeStep {
    SlotId slot;
    SlotId parent;
    ArcId arc;
    Dir dir;
  };

  std::vector<SlotId> block_first_slot_;  // num_blocks + 1 entries
  std::vector<BlockId> slot_block_;
  std::vector<NodeId> slot_node_;
  std::vector<std::array<SlotId, kNumCorners>> corner_slots_;
  // Block b's spanning tree is tree_steps_[block_first_step_[b] .. block_first_step_[b + 1]), its
  // parents always before their children; every other slot of b (its (-,-,-) corner, and any
  // slot the tree does not reach) is at the origin.
  std::vector<int32_t> block_first_step_;  // num_blocks + 1 entries
  std::vector<TreeStep> tree_steps_;
};

}  // namespace ispq

#endif  // ISPQ_CORE_BLOCK_NODE_POSITIONS_H_
