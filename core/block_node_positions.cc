// SPDX-License-Identifier: Apache-2.0
#include "core/block_node_positions.h"

#include <algorithm>

namespace ispq {

BlockNodeSlots::BlockNodeSlots(const TMesh& mesh) {
  const int num_blocks = mesh.num_blocks();
  block_first_slot_.reserve(num_blocks + 1);
  corner_slots_.resize(num_blocks);
  // A block's boundary is connected, so it has at most one node more than arcs.
  size_t boundary_arcs = 0;
  for (BlockId b = 0; b < num_blocks; ++b) boundary_arcs += mesh.block_arcs(b).size();
  slot_node_.reserve(boundary_arcs + num_blocks);
  slot_block_.reserve(boundary_arcs + num_blocks);
  tree_steps_.reserve(boundary_arcs);
  std::vector<NodeId> nodes;
  std::vector<uint8_t> listed(mesh.num_nodes(), 0);  // in `nodes` of the current block
  // Per block: slots for the endpoints of its boundary arcs, ascending by node id. Each node
  // ends about three arcs of a block, so it is listed once before sorting, not once per arc.
  for (BlockId b = 0; b < num_blocks; ++b) {
    block_first_slot_.push_back(static_cast<SlotId>(slot_node_.size()));
    nodes.clear();
    for (const BlockArc& ba : mesh.block_arcs(b)) {
      for (const NodeId n : {mesh.arc_from(ba.arc), mesh.arc_to(ba.arc)}) {
        if (listed[n]) continue;
        listed[n] = 1;
        nodes.push_back(n);
      }
    }
    std::sort(nodes.begin(), nodes.end());
    for (NodeId n : nodes) {
      listed[n] = 0;
      slot_node_.push_back(n);
      slot_block_.push_back(b);
    }
  }
  block_first_slot_.push_back(static_cast<SlotId>(slot_node_.size()));
  block_first_step_.reserve(num_blocks + 1);

  // Breadth-first spanning tree of each block's boundary graph from its (-,-,-) corner, over
  // that graph in flat arrays (edges grouped by their first slot) and a node -> slot map that is
  // filled for one block at a time.
  std::vector<SlotId> slot_at_node(mesh.num_nodes(), kNoId);
  std::vector<int32_t> edge_begin;
  std::vector<TreeStep> edges;
  std::vector<uint8_t> reached;
  std::vector<SlotId> queue;
  for (BlockId b = 0; b < num_blocks; ++b) {
    const SlotId first = block_first_slot_[b];
    const int count = block_first_slot_[b + 1] - first;
    for (SlotId s = first; s < first + count; ++s) slot_at_node[slot_node_[s]] = s;
    for (int c = 0; c < kNumCorners; ++c) {
      corner_slots_[b][c] = slot_at_node[mesh.block_corner(b, c)];
    }
    const std::span<const BlockArc> arcs = mesh.block_arcs(b);
    edge_begin.assign(count + 1, 0);
    for (const BlockArc& ba : arcs) {
      ++edge_begin[slot_at_node[mesh.arc_from(ba.arc)] - first + 1];
      ++edge_begin[slot_at_node[mesh.arc_to(ba.arc)] - first + 1];
    }
    for (int i = 0; i < count; ++i) edge_begin[i + 1] += edge_begin[i];
    edges.resize(2 * arcs.size());
    for (const BlockArc& ba : arcs) {
      const SlotId from = slot_at_node[mesh.arc_from(ba.arc)];
      const SlotId to = slot_at_node[mesh.arc_to(ba.arc)];
      edges[edge_begin[from - first]++] = {to, from, ba.arc, ba.dir};
      edges[edge_begin[to - first]++] = {from, to, ba.arc, Opposite(ba.dir)};
    }
    // Each slot's edges now end where the next slot's begin.
    reached.assign(count, 0);
    const SlotId root = corner_slots_[b][kMinCorner];
    block_first_step_.push_back(static_cast<int32_t>(tree_steps_.size()));
    reached[root - first] = 1;
    queue.assign(1, root);
    for (size_t i = 0; i < queue.size(); ++i) {
      const int local = queue[i] - first;
      for (int e = local == 0 ? 0 : edge_begin[local - 1]; e < edge_begin[local]; ++e) {
        const TreeStep& step = edges[e];
        if (reached[step.slot - first]) continue;
        reached[step.slot - first] = 1;
        tree_steps_.push_back(step);
        queue.push_back(step.slot);
      }
    }
    // A validated block's boundary is connected; anything unreached stays at the origin.
    for (SlotId s = first; s < first + count; ++s) slot_at_node[slot_node_[s]] = kNoId;
  }
  block_first_step_.push_back(static_cast<int32_t>(tree_steps_.size()));
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
  for (BlockId b = 0; b + 1 < static_cast<BlockId>(block_first_slot_.size()); ++b) {
    ComputeBlockPositions(b, q, positions);
  }
}

void BlockNodeSlots::ComputeBlockPositions(BlockId b, std::span<const int64_t> q,
                                           std::span<IntVec3> positions) const {
  std::fill(positions.begin() + block_first_slot_[b], positions.begin() + block_first_slot_[b + 1],
            IntVec3{0, 0, 0});
  for (int32_t i = block_first_step_[b]; i < block_first_step_[b + 1]; ++i) {
    const TreeStep& step = tree_steps_[i];
    positions[step.slot] = AddAlong(positions[step.parent], step.dir, q[step.arc]);
  }
}

bool BlockNodeSlots::PositionsDependOn(BlockId b, std::span<const uint8_t> marked_arcs) const {
  for (int32_t i = block_first_step_[b]; i < block_first_step_[b + 1]; ++i) {
    if (marked_arcs[tree_steps_[i].arc] != 0) return true;
  }
  return false;
}

}  // namespace ispq
