#include "core/separation_search_tables.h"

#include <algorithm>
#include <optional>

#include "core/halfarc_neighborhood.h"

namespace ispq {

namespace {

// Sum over the arcs of 2 * (blocks around the arc): the halfarc blocks of the whole mesh.
size_t HalfarcBlockPairs(const TMesh& mesh) {
  size_t pairs = 0;
  for (ArcId a = 0; a < mesh.num_arcs(); ++a) pairs += 2 * mesh.arc_blocks(a).size();
  return pairs;
}

// Sum over the halfpatches of their cycle sizes: a bound on the side slots, on the fan crossings
// (each is a side at a distinct node of its cycle) and on the critical sides (each is a side at
// a node of its cycle) of the whole mesh.
size_t CycleHalfarcs(const TMesh& mesh) {
  size_t halfarcs = 0;
  for (PatchId p = 0; p < mesh.num_patches(); ++p) halfarcs += 2 * mesh.patch_cycle(p).size();
  return halfarcs;
}

}  // namespace

SeparationSearchTables::SeparationSearchTables(const TMesh& mesh)
    : mesh_(mesh),
      slots_(mesh),
      configs_(mesh),
      sorted_outgoing_(mesh.num_nodes(), mesh.num_halfarcs()),
      halfarc_blocks_(mesh.num_halfarcs(), HalfarcBlockPairs(mesh)),
      fan_crossings_(slots_.num_slots(), CycleHalfarcs(mesh)),
      critical_sides_(mesh.num_nodes(), CycleHalfarcs(mesh)),
      side_slots_(mesh.num_halfpatches(), CycleHalfarcs(mesh)) {
  config_start_slot_.reserve(configs_.size());
  for (int i = 0; i < configs_.size(); ++i) {
    config_start_slot_.push_back(slots_.Find(configs_[i].start_block, configs_[i].start_node));
  }
}

void SeparationSearchTables::BuildSortedOutgoing(NodeId n) {
  outgoing_.assign(mesh_.outgoing_halfarcs(n).begin(), mesh_.outgoing_halfarcs(n).end());
  std::sort(outgoing_.begin(), outgoing_.end());
  sorted_outgoing_.Open(n);
  for (HalfarcId h : outgoing_) sorted_outgoing_.Push(h);
}

// Halfarc 2a's blocks around it are the arc's blocks as listed (core/tmesh.h); halfarc 2a + 1
// runs against the arc's direction, from its head to its tail, with its own radial order.
void SeparationSearchTables::BuildHalfarcBlocks(HalfarcId h) {
  if ((h & 1) == 0) {
    const std::span<const BlockId> blocks = mesh_.arc_blocks(ArcOf(h));
    around_.assign(blocks.begin(), blocks.end());
  } else {
    BlocksAroundHalfarc(mesh_, h, &around_);
  }
  halfarc_blocks_.Open(h);
  for (BlockId b : around_) {
    // Every block around a halfarc of a validated mesh has the arc on its boundary.
    const std::optional<Dir> dir = mesh_.HalfarcDirInBlock(h, b);
    if (!dir.has_value()) continue;
    halfarc_blocks_.Push({b, *dir, slots_.Find(b, mesh_.head(h))});
  }
}

void SeparationSearchTables::BuildSideSlots(HalfpatchId hp) {
  side_slots_.Open(hp);
  const BlockId owner = mesh_.halfpatch_block(hp);
  if (owner == kNoId) return;
  for (int i = 0; i < mesh_.halfpatch_cycle_size(hp); ++i) {
    side_slots_.Push(slots_.Find(owner, mesh_.tail(mesh_.HalfpatchCycleAt(hp, i))));
  }
}

// Block b's sides, in its halfpatch order, add themselves to the slots of the nodes on their
// cycles, so the sides of each slot come in that order; a node twice in a cycle counts once.
void SeparationSearchTables::BuildFanCrossings(BlockId b) {
  const SlotId first = slots_.first_slot(b);
  const int count = slots_.end_slot(b) - first;
  // The owner's and the across block's slots of every side (built first: building one list
  // moves the spans of the others).
  for (const HalfpatchId side : mesh_.block_halfpatches(b)) {
    if (mesh_.halfpatch_block(side) != b) continue;  // its slots are another block's
    SideSlots(side);
    SideSlots(side ^ 1);
  }
  // Calls `visit(local slot, side, i)` for every (slot, side through its node) pair, the node at
  // position i of the side's cycle.
  const auto for_each_pair = [&](const auto& visit) {
    last_side_.assign(count, kNoId);
    for (const HalfpatchId side : mesh_.block_halfpatches(b)) {
      if (mesh_.halfpatch_block(side) != b) continue;
      const std::span<const SlotId> cycle = side_slots_[side];
      for (int i = 0; i < static_cast<int>(cycle.size()); ++i) {
        // A validated block has a slot for every node of its sides' cycles.
        if (cycle[i] == kNoId || last_side_[cycle[i] - first] == side) continue;
        last_side_[cycle[i] - first] = side;
        visit(cycle[i] - first, side, i);
      }
    }
  };
  crossing_end_.assign(count + 1, 0);  // counts, then prefix sums, then each slot's end
  for_each_pair([&](int32_t local, HalfpatchId, int) { ++crossing_end_[local + 1]; });
  for (int i = 0; i < count; ++i) crossing_end_[i + 1] += crossing_end_[i];
  crossings_.resize(crossing_end_[count]);
  for_each_pair([&](int32_t local, HalfpatchId side, int i) {
    // Position i of the side's cycle is position (size - i) % size of the other side's, whose
    // slots are the block across's (none on the boundary).
    const std::span<const SlotId> across = side_slots_[side ^ 1];
    const int size = mesh_.halfpatch_cycle_size(side);
    crossings_[crossing_end_[local]++] = {side, across.empty() ? kNoId : across[(size - i) % size]};
  });
  for (int i = 0; i < count; ++i) {
    fan_crossings_.Open(first + i);
    for (int e = i == 0 ? 0 : crossing_end_[i - 1]; e < crossing_end_[i]; ++e) {
      fan_crossings_.Push(crossings_[e]);
    }
  }
}

void SeparationSearchTables::BuildCriticalSides(NodeId n) {
  critical_sides_.Open(n);
  for (HalfpatchId g : mesh_.node_halfpatches(n)) {
    const PatchId p = PatchOf(g);
    const HalfpatchId side = g ^ 1;  // the reference tests the side across each halfpatch
    const BlockId b = mesh_.halfpatch_block(side);
    if (!mesh_.patch_critical(p) || b == kNoId) continue;
    critical_sides_.Push({side, slots_.Find(b, n), AxisOf(mesh_.patch_face_side(p, SideOf(side)))});
  }
}

size_t SeparationSearchTables::num_built_values() const {
  return sorted_outgoing_.num_values() + halfarc_blocks_.num_values() +
         fan_crossings_.num_values() + critical_sides_.num_values() + side_slots_.num_values();
}

}  // namespace ispq
