// SPDX-License-Identifier: Apache-2.0
#include "core/separation_search_tables.h"

#include <algorithm>
#include <optional>

#include "core/halfarc_neighborhood.h"

namespace ispq {

namespace {

// Where each arc's (arc, block) pairs start, in the order of mesh.arc_blocks; the last entry is
// their number.
std::vector<uint32_t> ArcFirstPair(const TMesh& mesh) {
  std::vector<uint32_t> first(mesh.num_arcs() + 1, 0);
  for (ArcId a = 0; a < mesh.num_arcs(); ++a) {
    first[a + 1] = first[a] + static_cast<uint32_t>(mesh.arc_blocks(a).size());
  }
  return first;
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
      parallel_classes_(mesh),
      sorted_outgoing_(mesh.num_nodes(), mesh.num_halfarcs()),
      arc_first_pair_(ArcFirstPair(mesh)),
      halfarc_blocks_(mesh.num_halfarcs(), 2 * static_cast<size_t>(arc_first_pair_.back())),
      fan_crossings_(slots_.num_slots(), CycleHalfarcs(mesh)),
      critical_sides_(mesh.num_nodes(), CycleHalfarcs(mesh)),
      side_slots_(mesh.num_halfpatches(), CycleHalfarcs(mesh)),
      block_passed_(mesh.num_blocks(), 0),
      arcs_in_blocks_(MakeZeroedArray<ArcInBlock>(arc_first_pair_.back())),
      slot_of_node_(mesh.num_nodes(), kNoId) {
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

void SeparationSearchTables::MapNodesOf(BlockId b, bool mapped) {
  for (SlotId s = slots_.first_slot(b); s < slots_.end_slot(b); ++s) {
    slot_of_node_[slots_.node_of(s)] = mapped ? s : kNoId;
  }
}

void SeparationSearchTables::PassSidesOnce(BlockId b) {
  block_passed_[b] |= kSidesPassed;
  MapNodesOf(b, true);
  for (const HalfpatchId side : mesh_.block_halfpatches(b)) {
    if (mesh_.halfpatch_block(side) != b || side_slots_.built(side)) continue;  // not b's
    side_slots_.Open(side);
    for (int i = 0; i < mesh_.halfpatch_cycle_size(side); ++i) {
      side_slots_.Push(slot_of_node_[mesh_.tail(mesh_.HalfpatchCycleAt(side, i))]);
    }
  }
  MapNodesOf(b, false);
}

void SeparationSearchTables::PassArcsOnce(BlockId b) {
  block_passed_[b] |= kArcsPassed;
  MapNodesOf(b, true);
  ArcId previous = kNoId;
  for (const BlockArc& ba : mesh_.block_arcs(b)) {
    if (ba.arc == previous) continue;  // the first listing wins, as in a lookup
    previous = ba.arc;
    const std::span<const BlockId> blocks = mesh_.arc_blocks(ba.arc);
    const auto it = std::find(blocks.begin(), blocks.end(), b);
    if (it == blocks.end()) continue;  // a validated mesh lists every block of an arc
    arcs_in_blocks_[arc_first_pair_[ba.arc] + (it - blocks.begin())] = {
        ba.dir, slot_of_node_[mesh_.arc_from(ba.arc)] + 1, slot_of_node_[mesh_.arc_to(ba.arc)] + 1};
  }
  MapNodesOf(b, false);
}

void SeparationSearchTables::AddUnlistedSide(HalfpatchId hp) {
  side_slots_.Open(hp);
  for (int i = 0; i < mesh_.halfpatch_cycle_size(hp); ++i) side_slots_.Push(kNoId);
}

// Halfarc 2a's blocks around it are the arc's blocks as listed (core/tmesh.h); halfarc 2a + 1
// runs against the arc's direction, from its head to its tail, with its own radial order.
void SeparationSearchTables::BuildHalfarcBlocks(HalfarcId h) {
  const ArcId a = ArcOf(h);
  const std::span<const BlockId> blocks = mesh_.arc_blocks(a);
  if ((h & 1) == 0) {
    around_.assign(blocks.begin(), blocks.end());
  } else {
    BlocksAroundHalfarc(mesh_, h, &around_);
  }
  halfarc_blocks_.Open(h);
  for (BlockId b : around_) {
    const auto it = std::find(blocks.begin(), blocks.end(), b);
    const ArcInBlock* entry = nullptr;
    if (it != blocks.end()) {
      PassArcs(b);
      entry = &arcs_in_blocks_[arc_first_pair_[a] + (it - blocks.begin())];
    }
    if (entry == nullptr || entry->from_slot_plus_one == 0) {
      // A block around the halfarc whose lists disagree with the arc's (no validated mesh has
      // one) is looked up; one without the arc on its boundary is left out.
      const std::optional<Dir> dir = mesh_.HalfarcDirInBlock(h, b);
      if (dir.has_value()) halfarc_blocks_.Push({b, *dir, slots_.Find(b, mesh_.head(h))});
    } else if ((h & 1) == 0) {
      halfarc_blocks_.Push({b, entry->dir, entry->to_slot_plus_one - 1});
    } else {
      halfarc_blocks_.Push({b, Opposite(entry->dir), entry->from_slot_plus_one - 1});
    }
  }
}

// The sides of slot s's block through its node, in the block's halfpatch order, each with the
// slot of the node in the block across. A slot at a time: a fan enters a block at one or two of
// its slots, and building the crossings of all of them (with the sides of every block across)
// was most of the work of a large run's first searches.
void SeparationSearchTables::BuildFanCrossings(SlotId s) {
  const BlockId b = slots_.block_of(s);
  const NodeId n = slots_.node_of(s);
  const std::span<const HalfpatchId> at_node = mesh_.node_halfpatches(n);  // ascending
  fan_crossings_.Open(s);
  for (const HalfpatchId side : mesh_.block_halfpatches(b)) {
    if (mesh_.halfpatch_block(side) != b) continue;  // another block's side
    if (!std::binary_search(at_node.begin(), at_node.end(), side)) continue;
    const BlockId across = mesh_.halfpatch_block(side ^ 1);
    fan_crossings_.Push({side, across == kNoId ? kNoId : slots_.Find(across, n)});
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
