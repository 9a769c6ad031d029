#include "core/block_node_positions.h"

#include <algorithm>

namespace ispq {

BlockNodeSlots::BlockNodeSlots(const TMesh& mesh) {
  const int num_blocks = mesh.num_blocks();
  block_first_slot_.reserve(num_blocks + 1);
  corner_slots_.resize(num_blocks);
  std::vector<NodeId> nodes;
  // Per block: slots for the endpoints of its boundary arcs, ascending by node id.
  for (BlockId b = 0; b < num_blocks; ++b) {
    block_first_slot_.push_back(static_cast<SlotId>(slot_node_.size()));
    nodes.clear();
    for (const BlockArc& ba : mesh.block_arcs(b)) {
      nodes.push_back(mesh.arc_from(ba.arc));
      nodes.push_back(mesh.arc_to(ba.arc));
    }
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    for (NodeId n : nodes) {
      slot_node_.push_back(n);
      slot_block_.push_back(b);
    }
  }
  block_first_slot_.push_back(static_cast<SlotId>(slot_node_.size()));

  // Breadth-first spanning tree of each block's boundary graph from its (-,-,-) corner.
  std::vector<std::vector<TreeStep>> adjacency;
  std::vector<uint8_t> reached;
  std::vector<SlotId> queue;
  for (BlockId b = 0; b < num_blocks; ++b) {
    for (int c = 0; c < kNumCorners; ++c) corner_slots_[b][c] = Find(b, mesh.block_corner(b, c));
    const SlotId first = block_first_slot_[b];
    const int count = block_first_slot_[b + 1] - first;
    adjacency.assign(count, {});
    for (const BlockArc& ba : mesh.block_arcs(b)) {
      const SlotId from = Find(b, mesh.arc_from(ba.arc));
      const SlotId to = Find(b, mesh.arc_to(ba.arc));
      adjacency[from - first].push_back({to, from, ba.arc, ba.dir});
      adjacency[to - first].push_back({from, to, ba.arc, Opposite(ba.dir)});
    }
    reached.assign(count, 0);
    const SlotId root = corner_slots_[b][kMinCorner];
    roots_.push_back(root);
    reached[root - first] = 1;
    queue.assign(1, root);
    for (size_t i = 0; i < queue.size(); ++i) {
      for (const TreeStep& step : adjacency[queue[i] - first]) {
        if (reached[step.slot - first]) continue;
        reached[step.slot - first] = 1;
        tree_steps_.push_back(step);
        queue.push_back(step.slot);
      }
    }
    // A validated block's boundary is connected; anything unreached would stay at the origin.
    for (int i = 0; i < count; ++i) {
      if (!reached[i]) roots_.push_back(first + i);
    }
  }
}

SlotId BlockNodeSlots::Find(BlockId b, NodeId n) const {
  const auto begin = slot_node_.begin() + block_first_slot_[b];
  const auto end = slot_node_.begin() + block_first_slot_[b + 1];
  const auto it = std::lower_bound(begin, end, n);
  if (it == end || *it != n) return kNoId;
  return static_cast<SlotId>(it - slot_node_.begin());
}

void BlockNodeSlots::ComputePositions(std::span<const int64_t> q,
                                      std::span<IntVec3> positions) const {
  for (SlotId root : roots_) positions[root] = {0, 0, 0};
  for (const TreeStep& step : tree_steps_) {
    positions[step.slot] = AddAlong(positions[step.parent], step.dir, q[step.arc]);
  }
}

}  // namespace ispq
