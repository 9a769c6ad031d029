// SPDX-License-Identifier: Apache-2.0
// The mesh tables of the separation search (core/README.md, section Tables and cost): everything it
// reads that depends on the mesh alone, shared by the searches of one mesh (core/separation_check.h
// runs two, one after the other on one thread).
//
// The slots and the start configurations are built with the tables; every per-element list is
// built the first time a search asks for it (core/on_demand_lists.h), from one pass over each
// block it involves. A search only reads them around the nodes it pops and the blocks of its
// fans, and on a q with few zero-length arcs that is a small part of the mesh: building all of
// them up front was most of the wait for a large run's first valid q, whose searches pop little
// more than the critical links.
#ifndef ISPQ_CORE_SEPARATION_SEARCH_TABLES_H_
#define ISPQ_CORE_SEPARATION_SEARCH_TABLES_H_

#include <cstdint>
#include <span>
#include <vector>

#include "core/block_node_positions.h"
#include "core/on_demand_lists.h"
#include "core/parallel_classes.h"
#include "core/separation_start_configurations.h"
#include "core/tmesh.h"
#include "core/zeroed_array.h"

namespace ispq {

// A block around a halfarc (in the radial order around it), the halfarc's direction in the
// block's frame and the block's slot of the halfarc's head.
struct HalfarcInBlock {
  BlockId block;
  Dir dir;
  SlotId head_slot;
  bool operator==(const HalfarcInBlock&) const = default;
};

// A halfpatch side owned by a slot's block that passes through the slot's node, and the slot of
// the same node in the block across it (kNoId on the boundary). The fan crosses these.
struct FanCrossing {
  HalfpatchId side;
  SlotId neighbor_slot;
  bool operator==(const FanCrossing&) const = default;
};

// A side of a critical patch at a node that has a block: the block's slot of the node and the
// patch normal's axis in the block's frame (violation test (c)).
struct CriticalSide {
  HalfpatchId side;
  SlotId slot;
  int normal_axis;
  bool operator==(const CriticalSide&) const = default;
};

// The accessors that build a list are not const: the tables grow as searches read them. One
// thread uses them at a time; a span they return is valid until the next call that builds.
class SeparationSearchTables {
 public:
  // The mesh must outlive the tables.
  explicit SeparationSearchTables(const TMesh& mesh);

  const BlockNodeSlots& slots() const { return slots_; }
  const SeparationStartConfigurations& configs() const { return configs_; }
  const ParallelClasses& parallel_classes() const { return parallel_classes_; }
  SlotId config_start_slot(int config) const { return config_start_slot_[config]; }

  // Outgoing halfarcs of node n, ascending by id.
  std::span<const HalfarcId> SortedOutgoing(NodeId n) {
    if (!sorted_outgoing_.built(n)) BuildSortedOutgoing(n);
    return sorted_outgoing_[n];
  }
  // The blocks around halfarc h in its radial order. HalfarcBlockAt(HalfarcBlocksIndex(h) + k)
  // is entry k for good (h's list built).
  std::span<const HalfarcInBlock> HalfarcBlocks(HalfarcId h) {
    if (!halfarc_blocks_.built(h)) BuildHalfarcBlocks(h);
    return halfarc_blocks_[h];
  }
  int32_t HalfarcBlocksIndex(HalfarcId h) const { return halfarc_blocks_.first_index(h); }
  const HalfarcInBlock& HalfarcBlockAt(int32_t index) const { return halfarc_blocks_.value(index); }
  // The sides the fan may cross at slot s, in its block's halfpatch order.
  std::span<const FanCrossing> FanCrossings(SlotId s) {
    if (!fan_crossings_.built(s)) BuildFanCrossings(s);
    return fan_crossings_[s];
  }
  // The sides of critical patches at node n (ascending by incident halfpatch) that have a block.
  std::span<const CriticalSide> CriticalSides(NodeId n) {
    if (!critical_sides_.built(n)) BuildCriticalSides(n);
    return critical_sides_[n];
  }
  // The owner's slots of the nodes on halfpatch hp's cycle, in cycle order (empty without an
  // owner, on the boundary).
  std::span<const SlotId> SideSlots(HalfpatchId hp) {
    const BlockId owner = mesh_.halfpatch_block(hp);
    if (owner == kNoId) return {};
    PassSides(owner);
    if (!side_slots_.built(hp)) AddUnlistedSide(hp);
    return side_slots_[hp];
  }

  // Values in the built lists, for tests and measurements of how much a search needed.
  size_t num_built_values() const;

 private:
  // An arc (as halfarc 2a) in one of its blocks: its direction in the block's frame and the
  // block's slots of its ends, plus one (0: the block's pass did not write it). One per
  // (arc, block) pair, in the order of mesh.arc_blocks.
  struct ArcInBlock {
    Dir dir;
    SlotId from_slot_plus_one;
    SlotId to_slot_plus_one;
  };
  // What block b alone determines, each once: the slots of the sides it owns (for its side
  // boxes) and its arcs in it (for halfarc lists), read through a node -> slot map of the block.
  // Binary searches of the block's slots and arcs per entry instead made the runs of the shared
  // set 5% slower (searches there reach every block, and the whole-mesh block pass this replaces
  // had the map).
  enum BlockPass : uint8_t { kSidesPassed = 1, kArcsPassed = 2 };
  void PassSides(BlockId b) {
    if ((block_passed_[b] & kSidesPassed) == 0) PassSidesOnce(b);
  }
  void PassArcs(BlockId b) {
    if ((block_passed_[b] & kArcsPassed) == 0) PassArcsOnce(b);
  }
  void PassSidesOnce(BlockId b);
  void PassArcsOnce(BlockId b);
  void MapNodesOf(BlockId b, bool mapped);
  // A side its owner does not list among its halfpatches (no validated mesh has one): no slots.
  void AddUnlistedSide(HalfpatchId hp);
  void BuildSortedOutgoing(NodeId n);
  void BuildHalfarcBlocks(HalfarcId h);
  void BuildFanCrossings(SlotId s);
  void BuildCriticalSides(NodeId n);

  const TMesh& mesh_;
  const BlockNodeSlots slots_;
  const SeparationStartConfigurations configs_;
  const ParallelClasses parallel_classes_;
  std::vector<SlotId> config_start_slot_;

  OnDemandLists<HalfarcId> sorted_outgoing_;      // per node
  std::vector<uint32_t> arc_first_pair_;          // per arc + 1: its first entry in arcs_in_blocks_
  OnDemandLists<HalfarcInBlock> halfarc_blocks_;  // per halfarc
  OnDemandLists<FanCrossing> fan_crossings_;      // per slot
  OnDemandLists<CriticalSide> critical_sides_;    // per node
  OnDemandLists<SlotId> side_slots_;              // per halfpatch with an owner

  std::vector<uint8_t> block_passed_;  // per block: BlockPass bits
  // Written by the passes of their blocks; zero before (unwritten: see core/zeroed_array.h).
  ZeroedArray<ArcInBlock> arcs_in_blocks_;
  std::vector<SlotId> slot_of_node_;  // of the block in its pass, kNoId elsewhere

  // Scratch of the builders.
  std::vector<HalfarcId> outgoing_;
  std::vector<BlockId> around_;
};

}  // namespace ispq

#endif  // ISPQ_CORE_SEPARATION_SEARCH_TABLES_H_
