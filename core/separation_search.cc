#include "core/separation_search.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <memory>
#include <utility>

#include "core/block_node_positions.h"
#include "core/flat_lists.h"
#include "core/halfarc_neighborhood.h"
#include "core/integer_box.h"
#include "core/separation_start_configurations.h"
#include "core/stamped_set.h"

namespace ispq {
namespace {

// A block around a halfarc (in the radial order around it), the halfarc's direction in the
// block's frame and the block's slot of the halfarc's head.
struct HalfarcInBlock {
  BlockId block;
  Dir dir;
  SlotId head_slot;
};

// A halfpatch side owned by a slot's block that passes through the slot's node, and the slot of
// the same node in the block across it (kNoId on the boundary). The fan crosses these.
struct FanCrossing {
  HalfpatchId side;
  SlotId neighbor_slot;
};

// A side of a critical patch at a node that has a block: the block's slot of the node and the
// patch normal's axis in the block's frame (violation test (c)).
struct CriticalSide {
  HalfpatchId side;
  SlotId slot;
  int normal_axis;
};

// One walk, stored once in an arena; its path is recovered through the parent links.
struct Walk {
  IntVec3 x;       // position of `node` relative to the start node, in the reference frame
  double cost;     // target length walked off the link axis
  int32_t parent;  // arena index, -1 for the start
  HalfarcId step;  // the halfarc that led here, kNoId for the start
  NodeId node;
  SlotId slot;        // (block used for the last step, node)
  int32_t k;          // number of halfarcs walked after branching
  Rotation rotation;  // M: reference frame -> frame of the slot's block
  DirSet walked;      // W
  DirSet monotone;    // M
  Dir step_dir;       // direction of `step` in the reference frame
  bool branched;
  // Branched and already past the start box along the monotone direction by more than negative
  // arcs could ever bring back: neither this walk nor any walk extending it can report.
  bool hopeless;
};

struct QueueEntry {
  double cost;
  int32_t k;
  int32_t walk;
};

// The reference's heap order (a std::priority_queue over (length, path size)): the smallest
// (cost, k) on top, and among equal keys the heap's own layout decides. That is deterministic
// for a given sequence of pushes and pops, so with the same pushes in the same order ties pop
// exactly as in the reference, and rows can be compared with upstream's one for one
// (tests/differential). Both block-box modes use it, so they differ in admissibility only.
struct PopsLater {
  bool operator()(const QueueEntry& a, const QueueEntry& b) const {
    return a.cost > b.cost || (a.cost == b.cost && a.k > b.k);
  }
};

// A candidate halfarc at the current node and its blocks in the fan (a range of fan_entries_).
struct Candidate {
  HalfarcId halfarc;
  int32_t begin;
  int32_t end;
};

// Adds coef * q_arc to a row, merging with an existing term of the same arc.
void AddTerm(std::vector<LinearTerm>& terms, ArcId arc, int32_t coef) {
  for (LinearTerm& t : terms) {
    if (t.var == arc) {
      t.coef += coef;
      return;
    }
  }
  terms.push_back({arc, coef});
}

void DropZeroTerms(std::vector<LinearTerm>& terms) {
  terms.erase(
      std::remove_if(terms.begin(), terms.end(), [](const LinearTerm& t) { return t.coef == 0; }),
      terms.end());
}

}  // namespace

// Everything that depends on the mesh alone (section 6.2): built once and shared by the
// searches of one mesh (core/separation_check.h runs two).
struct SeparationSearchTables {
  explicit SeparationSearchTables(const TMesh& mesh);

  const BlockNodeSlots slots;
  const SeparationStartConfigurations configs;
  std::vector<SlotId> config_start_slot;
  FlatLists<HalfarcId> sorted_outgoing;      // per node, ascending halfarc id
  FlatLists<HalfarcInBlock> halfarc_blocks;  // per halfarc, radial order
  FlatLists<FanCrossing> fan_crossings;      // per slot, in the block's halfpatch order
  FlatLists<CriticalSide> critical_sides;    // per node, ascending incident halfpatch
  FlatLists<SlotId> side_slots;              // per halfpatch: its owner's slots of its cycle
  std::vector<Rotation> crossing_rotation;   // per halfpatch: Rot(g)

 private:
  // An arc (as halfarc 2a) in one of its blocks: its direction in the block's frame and the
  // block's slots of its ends. One per (arc, block) pair, in the order of mesh.arc_blocks.
  struct ArcInBlock {
    Dir dir;
    SlotId from_slot = kNoId;
    SlotId to_slot = kNoId;
  };

  // side_slots and the arcs in their blocks, block by block through a node -> slot map of the
  // block: an array lookup instead of a binary search of the block's slots (and of its arcs)
  // for each of them, which was a third of building a check (10k arcs: 19 -> 14.3 ms with the
  // fan crossings read from side_slots). Returns the arcs in blocks for AddHalfarcBlocks.
  std::vector<ArcInBlock> AddSideSlotsAndArcsInBlocks(const TMesh& mesh,
                                                      std::span<const uint32_t> arc_first_pair);
  void AddHalfarcBlocks(const TMesh& mesh, std::span<const uint32_t> arc_first_pair,
                        std::span<const ArcInBlock> arcs_in_blocks);
  void AddFanCrossings(const TMesh& mesh);
};

std::vector<SeparationSearchTables::ArcInBlock> SeparationSearchTables::AddSideSlotsAndArcsInBlocks(
    const TMesh& mesh, std::span<const uint32_t> arc_first_pair) {
  for (HalfpatchId hp = 0; hp < mesh.num_halfpatches(); ++hp) {
    side_slots.AppendFilled(mesh.halfpatch_block(hp) == kNoId ? 0 : mesh.halfpatch_cycle_size(hp),
                            kNoId);
  }
  std::vector<ArcInBlock> arcs_in_blocks(arc_first_pair.back());
  std::vector<SlotId> slot_of_node(mesh.num_nodes(), kNoId);  // of the current block
  const auto map_nodes_of = [&](BlockId b, bool mapped) {
    for (SlotId s = slots.first_slot(b); s < slots.end_slot(b); ++s) {
      slot_of_node[slots.node_of(s)] = mapped ? s : kNoId;
    }
  };
  for (BlockId b = 0; b < mesh.num_blocks(); ++b) {
    map_nodes_of(b, true);
    for (const HalfpatchId side : mesh.block_halfpatches(b)) {
      if (mesh.halfpatch_block(side) != b) continue;  // not b's to fill
      const std::span<SlotId> cycle_slots = side_slots.MutableList(side);
      for (int i = 0; i < static_cast<int>(cycle_slots.size()); ++i) {
        cycle_slots[i] = slot_of_node[mesh.tail(mesh.HalfpatchCycleAt(side, i))];
      }
    }
    for (const BlockArc& ba : mesh.block_arcs(b)) {
      const std::span<const BlockId> blocks = mesh.arc_blocks(ba.arc);
      const auto it = std::find(blocks.begin(), blocks.end(), b);
      if (it == blocks.end()) continue;  // a validated mesh lists every block of an arc
      ArcInBlock& entry = arcs_in_blocks[arc_first_pair[ba.arc] + (it - blocks.begin())];
      if (entry.from_slot != kNoId) continue;  // the first listing wins, as in a lookup
      entry = {ba.dir, slot_of_node[mesh.arc_from(ba.arc)], slot_of_node[mesh.arc_to(ba.arc)]};
    }
    map_nodes_of(b, false);
  }
  return arcs_in_blocks;
}

// halfarc_blocks: the blocks around each halfarc in its radial order, read from the arcs in
// blocks (halfarc 2a + 1 runs against the arc's direction, from its head to its tail).
void SeparationSearchTables::AddHalfarcBlocks(const TMesh& mesh,
                                              std::span<const uint32_t> arc_first_pair,
                                              std::span<const ArcInBlock> arcs_in_blocks) {
  std::vector<BlockId> around;
  for (HalfarcId h = 0; h < mesh.num_halfarcs(); ++h) {
    halfarc_blocks.OpenList();
    const ArcId a = ArcOf(h);
    const std::span<const BlockId> blocks = mesh.arc_blocks(a);
    // Halfarc 2a's blocks around it are the arc's blocks as listed (core/tmesh.h).
    if ((h & 1) == 0) {
      around.assign(blocks.begin(), blocks.end());
    } else {
      BlocksAroundHalfarc(mesh, h, &around);
    }
    for (BlockId b : around) {
      const auto it = std::find(blocks.begin(), blocks.end(), b);
      const ArcInBlock* entry =
          it == blocks.end() ? nullptr : &arcs_in_blocks[arc_first_pair[a] + (it - blocks.begin())];
      // A block around the halfarc that does not list the arc (no validated mesh has one) is
      // looked up as it was before the block pass.
      if (entry == nullptr || entry->from_slot == kNoId) {
        halfarc_blocks.PushToLast({b, *mesh.HalfarcDirInBlock(h, b), slots.Find(b, mesh.head(h))});
      } else if ((h & 1) == 0) {
        halfarc_blocks.PushToLast({b, entry->dir, entry->to_slot});
      } else {
        halfarc_blocks.PushToLast({b, Opposite(entry->dir), entry->from_slot});
      }
    }
  }
}

// fan_crossings, block by block from side_slots: each side of the block adds itself to its
// slots (those of the nodes on its cycle), so the sides of each slot come in the block's
// halfpatch order.
void SeparationSearchTables::AddFanCrossings(const TMesh& mesh) {
  std::vector<HalfpatchId> last_side;  // per local slot: a node twice in a cycle counts once
  std::vector<int32_t> end;            // per local slot, after the fill below
  std::vector<FanCrossing> crossings;
  // Calls `visit(local slot, side, i)` for every (slot, side through its node) pair of block b,
  // the node at position i of the side's cycle.
  const auto for_each_pair = [&](BlockId b, const auto& visit) {
    const SlotId first = slots.first_slot(b);
    std::fill(last_side.begin(), last_side.end(), kNoId);
    for (const HalfpatchId side : mesh.block_halfpatches(b)) {
      if (mesh.halfpatch_block(side) != b) continue;  // its slots are another block's
      const std::span<const SlotId> cycle = side_slots[side];
      for (int i = 0; i < static_cast<int>(cycle.size()); ++i) {
        // A validated block has a slot for every node of its sides' cycles; anything else is
        // skipped, as a lookup of the slot would skip it.
        if (cycle[i] == kNoId || last_side[cycle[i] - first] == side) continue;
        last_side[cycle[i] - first] = side;
        visit(cycle[i] - first, side, i);
      }
    }
  };
  for (BlockId b = 0; b < mesh.num_blocks(); ++b) {
    const int count = slots.end_slot(b) - slots.first_slot(b);
    last_side.assign(count, kNoId);
    end.assign(count + 1, 0);  // counts, then prefix sums, then each slot's end
    for_each_pair(b, [&](int32_t local, HalfpatchId, int) { ++end[local + 1]; });
    for (int i = 0; i < count; ++i) end[i + 1] += end[i];
    crossings.resize(end[count]);
    for_each_pair(b, [&](int32_t local, HalfpatchId side, int i) {
      // Position i of the side's cycle is position (size - i) % size of the other side's, whose
      // slots are the block across's (none on the boundary).
      const std::span<const SlotId> across = side_slots[side ^ 1];
      const int size = mesh.halfpatch_cycle_size(side);
      crossings[end[local]++] = {side, across.empty() ? kNoId : across[(size - i) % size]};
    });
    for (int i = 0; i < count; ++i) {
      fan_crossings.OpenList();
      for (int e = i == 0 ? 0 : end[i - 1]; e < end[i]; ++e) fan_crossings.PushToLast(crossings[e]);
    }
  }
}

// The buffers of one call, sized by the mesh and rewritten by every call: nothing in them
// outlives a call, so the two searches of core/separation_check.h, which run one after the
// other on one thread, share one set. They are a third of a search's memory, and first touching
// fresh pages is about half of what building a search costs (10k arcs: 19.5 ms cold, 9.8 warm).
struct SeparationSearchScratch {
  explicit SeparationSearchScratch(const BlockNodeSlots& slots, const TMesh& mesh);

  std::vector<IntVec3> positions;
  std::vector<IntBox> side_boxes;
  std::vector<Walk> arena;
  std::vector<QueueEntry> queue;
  StampedSet seen_pre, seen_post, branch_offs, pre_branch_arcs, in_fan;
  std::vector<Rotation> fan_rotation, fan_to_reference;
  std::vector<SlotId> fan_slot;
  std::vector<int8_t> fan_admissible;
  std::vector<BlockId> fan_order;
  std::vector<Candidate> candidates;
  std::vector<int32_t> fan_entries;
  std::array<std::vector<ArcId>, kNumDirs> walked_arcs;
};

SeparationSearchScratch::SeparationSearchScratch(const BlockNodeSlots& slots, const TMesh& mesh)
    : positions(slots.num_slots()),
      side_boxes(mesh.num_halfpatches()),
      fan_rotation(mesh.num_blocks()),
      fan_to_reference(mesh.num_blocks()),
      fan_slot(mesh.num_blocks()),
      fan_admissible(mesh.num_blocks()) {
  seen_pre.Resize(mesh.num_nodes());
  seen_post.Resize(mesh.num_nodes());
  branch_offs.Resize(mesh.num_halfarcs());
  pre_branch_arcs.Resize(mesh.num_arcs());
  in_fan.Resize(mesh.num_blocks());
}

class SeparationSearch::Impl {
 public:
  Impl(const TMesh& mesh, std::shared_ptr<const SeparationSearchTables> tables,
       std::shared_ptr<SeparationSearchScratch> scratch, SeparationSearchOptions options);
  const std::shared_ptr<const SeparationSearchTables>& tables() const { return tables_; }
  const std::shared_ptr<SeparationSearchScratch>& scratch() const { return scratch_; }

  int64_t FindViolations(std::span<const int64_t> q,
                         const std::function<bool(SeparationViolation&)>& sink);

 private:
  // Per-call state that depends on q only.
  void ComputeGeometry(std::span<const int64_t> q);
  IntBox StartBox(int config, std::span<const int64_t> q) const;

  // One search (separation.md section 3.4); true and `violation` filled on the first hit.
  bool Search(int config, std::span<const int64_t> q, SeparationViolation& violation);
  void Push(const Walk& walk);

  void BuildFan(const Walk& walk, bool at_start_box);
  void BuildCandidates(const Walk& walk);
  bool FindViolationDirs(const Walk& walk, bool at_start_box, std::span<const int64_t> q,
                         DirSet& dirs, SeparationTargetKind& kind, int32_t& target) const;
  void Expand(int32_t walk_index, bool at_start_box, std::span<const int64_t> q);
  bool Admissible(const Walk& walk, bool at_start_box, BlockId block);
  // Touches(box_, other) for the current search, whose start box is never inverted.
  bool TouchesStartBox(const IntBox& other) const {
    return !IsInverted(other) && Overlap(box_, other);
  }
  IntBox PatchBox(const Walk& walk, HalfpatchId side, SlotId slot, Rotation to_reference) const;
  void BuildViolation(int config, int32_t walk_index, DirSet dirs, SeparationTargetKind kind,
                      int32_t target, SeparationViolation& violation);

  const TMesh& mesh_;
  const SeparationSearchOptions options_;
  // Mesh tables (section 6.2), shared; the references name their parts.
  const std::shared_ptr<const SeparationSearchTables> tables_;
  const BlockNodeSlots& slots_;
  const SeparationStartConfigurations& configs_;
  const std::vector<SlotId>& config_start_slot_;
  const FlatLists<HalfarcId>& sorted_outgoing_;
  const FlatLists<HalfarcInBlock>& halfarc_blocks_;
  const FlatLists<FanCrossing>& fan_crossings_;
  const FlatLists<CriticalSide>& critical_sides_;
  const FlatLists<SlotId>& side_slots_;
  const std::vector<Rotation>& crossing_rotation_;

  // Buffers, possibly shared with another search of the mesh; the references name their parts.
  const std::shared_ptr<SeparationSearchScratch> scratch_;
  // Geometry of the current q (section 6.3).
  std::vector<IntVec3>& positions_;  // per slot
  std::vector<IntBox>& side_boxes_;  // per owned halfpatch side, in the owner's frame

  // State of the current search.
  IntBox box_{};
  DirSet link_axis_ = 0;
  std::vector<Walk>& arena_;
  std::vector<QueueEntry>& queue_;
  int hopeful_in_queue_ = 0;           // queued walks that are not hopeless
  int64_t negative_slack_ = 0;         // sum of -q_a over the arcs with q_a < 0
  StampedSet &seen_pre_, &seen_post_;  // over nodes
  StampedSet& branch_offs_;            // over halfarcs
  StampedSet& pre_branch_arcs_;        // over arcs
  // State of the current pop: the fan over blocks and the candidates.
  StampedSet& in_fan_;
  std::vector<Rotation>& fan_rotation_;      // M_b
  std::vector<Rotation>& fan_to_reference_;  // M_b^-1
  std::vector<SlotId>& fan_slot_;            // (b, current node)
  std::vector<int8_t>& fan_admissible_;      // -1 not evaluated yet at this node, else 0 or 1
  std::vector<BlockId>& fan_order_;
  std::vector<Candidate>& candidates_;
  std::vector<int32_t>& fan_entries_;  // indices into halfarc_blocks_.all_values()
  std::array<std::vector<ArcId>, kNumDirs>& walked_arcs_;  // L[d] while building rows
};

SeparationSearchTables::SeparationSearchTables(const TMesh& mesh) : slots(mesh), configs(mesh) {
  size_t halfarc_block_pairs = 0, cycle_halfarcs = 0;
  for (ArcId a = 0; a < mesh.num_arcs(); ++a) halfarc_block_pairs += 2 * mesh.arc_blocks(a).size();
  for (PatchId p = 0; p < mesh.num_patches(); ++p) cycle_halfarcs += 2 * mesh.patch_cycle(p).size();
  sorted_outgoing.Reserve(mesh.num_nodes(), mesh.num_halfarcs());
  halfarc_blocks.Reserve(mesh.num_halfarcs(), halfarc_block_pairs);
  fan_crossings.Reserve(slots.num_slots(), cycle_halfarcs);
  critical_sides.Reserve(mesh.num_nodes(), 0);
  side_slots.Reserve(mesh.num_halfpatches(), cycle_halfarcs);
  crossing_rotation.reserve(mesh.num_halfpatches());
  config_start_slot.reserve(configs.size());
  for (int i = 0; i < configs.size(); ++i) {
    config_start_slot.push_back(slots.Find(configs[i].start_block, configs[i].start_node));
  }
  std::vector<HalfarcId> outgoing;
  for (NodeId n = 0; n < mesh.num_nodes(); ++n) {
    outgoing.assign(mesh.outgoing_halfarcs(n).begin(), mesh.outgoing_halfarcs(n).end());
    std::sort(outgoing.begin(), outgoing.end());
    sorted_outgoing.Append(outgoing);
  }
  std::vector<uint32_t> arc_first_pair(mesh.num_arcs() + 1, 0);  // into arcs in blocks
  for (ArcId a = 0; a < mesh.num_arcs(); ++a) {
    arc_first_pair[a + 1] = arc_first_pair[a] + mesh.arc_blocks(a).size();
  }
  AddHalfarcBlocks(mesh, arc_first_pair, AddSideSlotsAndArcsInBlocks(mesh, arc_first_pair));
  AddFanCrossings(mesh);  // reads side_slots
  for (NodeId n = 0; n < mesh.num_nodes(); ++n) {
    critical_sides.OpenList();
    for (HalfpatchId g : mesh.node_halfpatches(n)) {
      const PatchId p = PatchOf(g);
      const HalfpatchId side = g ^ 1;  // the reference tests the side across each halfpatch
      const BlockId b = mesh.halfpatch_block(side);
      if (!mesh.patch_critical(p) || b == kNoId) continue;
      critical_sides.PushToLast(
          {side, slots.Find(b, n), AxisOf(mesh.patch_face_side(p, SideOf(side)))});
    }
  }
  for (HalfpatchId hp = 0; hp < mesh.num_halfpatches(); ++hp) {
    crossing_rotation.push_back(mesh.crossing_rotation(hp));
  }
}

SeparationSearch::Impl::Impl(const TMesh& mesh,
                             std::shared_ptr<const SeparationSearchTables> tables,
                             std::shared_ptr<SeparationSearchScratch> scratch,
                             SeparationSearchOptions options)
    : mesh_(mesh),
      options_(options),
      tables_(std::move(tables)),
      slots_(tables_->slots),
      configs_(tables_->configs),
      config_start_slot_(tables_->config_start_slot),
      sorted_outgoing_(tables_->sorted_outgoing),
      halfarc_blocks_(tables_->halfarc_blocks),
      fan_crossings_(tables_->fan_crossings),
      critical_sides_(tables_->critical_sides),
      side_slots_(tables_->side_slots),
      crossing_rotation_(tables_->crossing_rotation),
      scratch_(scratch != nullptr ? std::move(scratch)
                                  : std::make_shared<SeparationSearchScratch>(slots_, mesh)),
      positions_(scratch_->positions),
      side_boxes_(scratch_->side_boxes),
      arena_(scratch_->arena),
      queue_(scratch_->queue),
      seen_pre_(scratch_->seen_pre),
      seen_post_(scratch_->seen_post),
      branch_offs_(scratch_->branch_offs),
      pre_branch_arcs_(scratch_->pre_branch_arcs),
      in_fan_(scratch_->in_fan),
      fan_rotation_(scratch_->fan_rotation),
      fan_to_reference_(scratch_->fan_to_reference),
      fan_slot_(scratch_->fan_slot),
      fan_admissible_(scratch_->fan_admissible),
      fan_order_(scratch_->fan_order),
      candidates_(scratch_->candidates),
      fan_entries_(scratch_->fan_entries),
      walked_arcs_(scratch_->walked_arcs) {}

void SeparationSearch::Impl::ComputeGeometry(std::span<const int64_t> q) {
  slots_.ComputePositions(q, positions_);
  for (HalfpatchId hp = 0; hp < mesh_.num_halfpatches(); ++hp) {
    const std::span<const SlotId> cycle = side_slots_[hp];
    if (cycle.empty()) continue;
    IntBox box = PointBox(positions_[cycle.front()]);
    for (SlotId s : cycle) {
      const IntVec3& p = positions_[s];
      for (int i = 0; i < 3; ++i) {
        box.lo[i] = std::min(box.lo[i], p[i]);
        box.hi[i] = std::max(box.hi[i], p[i]);
      }
    }
    side_boxes_[hp] = box;
  }
}

// Node starts: the start point. Link starts: the segment from 0 to L * e with L the link's
// quantized length, bounds taken by the sign of e as in the reference (a negative L inverts the
// box, so nothing touches it); unbounded along e's axis for a cyclic link.
IntBox SeparationSearch::Impl::StartBox(int config, std::span<const int64_t> q) const {
  IntBox box = PointBox({0, 0, 0});
  const SeparationStartConfiguration& c = configs_[config];
  if (!c.is_link) return box;
  int64_t length = 0;
  for (HalfarcId h : mesh_.entity_halfarcs(c.entity)) length += q[ArcOf(h)];
  const int axis = AxisOf(c.link_dir);
  if (IsNegative(c.link_dir)) {
    box.lo[axis] = -length;
  } else {
    box.hi[axis] = length;
  }
  if (c.cyclic_link) {
    box.lo[axis] = std::numeric_limits<int64_t>::min();
    box.hi[axis] = std::numeric_limits<int64_t>::max();
  }
  return box;
}

int64_t SeparationSearch::Impl::FindViolations(
    std::span<const int64_t> q, const std::function<bool(SeparationViolation&)>& sink) {
  if (static_cast<int>(q.size()) != mesh_.num_arcs()) {
    std::fprintf(stderr, "SeparationSearch::FindViolations: q has %zu entries for %d arcs\n",
                 q.size(), mesh_.num_arcs());
    std::abort();
  }
  ComputeGeometry(q);
  negative_slack_ = 0;
  for (int64_t length : q) negative_slack_ += length < 0 ? -length : 0;
  int64_t found = 0;
  SeparationViolation violation;
  for (int config = 0; config < configs_.size(); ++config) {
    if (!Search(config, q, violation)) continue;
    ++found;
    if (!sink(violation)) break;
  }
  return found;
}

bool SeparationSearch::Impl::Search(int config, std::span<const int64_t> q,
                                    SeparationViolation& violation) {
  box_ = StartBox(config, q);
  // A collapsed link (negative length, only while simple rows are violated) has an inverted
  // start box that nothing touches: no block is admissible and nothing can be reported.
  if (IsInverted(box_)) return false;
  link_axis_ = configs_.link_axis(config);
  seen_pre_.Clear();
  seen_post_.Clear();
  branch_offs_.Clear();
  for (HalfarcId h : configs_.branch_offs(config)) branch_offs_.Insert(h);
  pre_branch_arcs_.Clear();
  for (ArcId a : configs_.pre_branch_arcs(config)) pre_branch_arcs_.Insert(a);
  arena_.clear();
  queue_.clear();
  hopeful_in_queue_ = 0;

  Walk start;
  start.x = {0, 0, 0};
  start.cost = 0;
  start.parent = -1;
  start.step = kNoId;
  start.node = configs_[config].start_node;
  start.slot = config_start_slot_[config];
  start.k = 0;
  start.rotation = Rotation();  // the identity: the start block's frame is the reference frame
  start.walked = 0;
  start.monotone = kAllDirBits & static_cast<DirSet>(~link_axis_);
  start.step_dir = Dir::kPosU;
  start.branched = false;
  start.hopeless = false;
  Push(start);

  // Every later walk extends a queued one, so once all queued walks are hopeless the search
  // cannot report anything and stops; this changes no result, only the work.
  while (hopeful_in_queue_ > 0) {
    std::pop_heap(queue_.begin(), queue_.end(), PopsLater());
    const int32_t index = queue_.back().walk;
    queue_.pop_back();
    if (!arena_[index].hopeless) --hopeful_in_queue_;
    StampedSet& seen = arena_[index].branched ? seen_post_ : seen_pre_;
    if (seen.Contains(arena_[index].node)) continue;
    seen.Insert(arena_[index].node);
    const Walk walk = arena_[index];

    // Every patch at the node contains the node, so while the walk's position lies in the start
    // box every patch box touches it and the fan may cross every patch.
    const bool at_start_box = TouchesStartBox(PointBox(walk.x));
    BuildFan(walk, at_start_box);
    BuildCandidates(walk);
    if (walk.branched) {
      DirSet dirs = 0;
      SeparationTargetKind kind = SeparationTargetKind::kNode;
      int32_t target = kNoId;
      if (FindViolationDirs(walk, at_start_box, q, dirs, kind, target)) {
        BuildViolation(config, index, dirs, kind, target, violation);
        return true;
      }
    }
    Expand(index, at_start_box, q);
  }
  return false;
}

void SeparationSearch::Impl::Push(const Walk& walk) {
  if (!walk.hopeless) ++hopeful_in_queue_;
  queue_.push_back({walk.cost, walk.k, static_cast<int32_t>(arena_.size())});
  arena_.push_back(walk);
  std::push_heap(queue_.begin(), queue_.end(), PopsLater());
}

IntBox SeparationSearch::Impl::PatchBox(const Walk& walk, HalfpatchId side, SlotId slot,
                                        Rotation to_reference) const {
  const IntVec3& at = positions_[slot];
  const IntBox& own = side_boxes_[side];
  const IntBox local = RotateBox(to_reference, IntBox{Subtract(own.lo, at), Subtract(own.hi, at)});
  return {Add(walk.x, local.lo), Add(walk.x, local.hi)};
}

// Section 3.5: breadth-first over the blocks around the node, crossing a patch only if its
// rectangle touches the start box; each block keeps the rotation of its first route.
void SeparationSearch::Impl::BuildFan(const Walk& walk, bool at_start_box) {
  in_fan_.Clear();
  fan_order_.clear();
  const auto add = [this](BlockId b, Rotation rotation, SlotId slot) {
    in_fan_.Insert(b);
    fan_rotation_[b] = rotation;
    fan_to_reference_[b] = rotation.Inverse();
    fan_slot_[b] = slot;
    fan_admissible_[b] = -1;
    fan_order_.push_back(b);
  };
  add(slots_.block_of(walk.slot), walk.rotation, walk.slot);
  for (size_t i = 0; i < fan_order_.size(); ++i) {
    const BlockId b = fan_order_[i];
    const SlotId slot = fan_slot_[b];
    for (const FanCrossing& crossing : fan_crossings_[slot]) {
      if (crossing.neighbor_slot == kNoId) continue;
      const BlockId across = slots_.block_of(crossing.neighbor_slot);
      if (in_fan_.Contains(across)) continue;
      if (!at_start_box &&
          !TouchesStartBox(PatchBox(walk, crossing.side, slot, fan_to_reference_[b]))) {
        continue;
      }
      add(across, crossing_rotation_[crossing.side].After(fan_rotation_[b]),
          crossing.neighbor_slot);
    }
  }
}

// Outgoing halfarcs in ascending id, each with its blocks that are in the fan (radial order);
// the reversal of the last recorded step is left out.
void SeparationSearch::Impl::BuildCandidates(const Walk& walk) {
  candidates_.clear();
  fan_entries_.clear();
  const HalfarcId reversal = walk.branched ? Twin(walk.step) : kNoId;
  const HalfarcInBlock* const all_entries = halfarc_blocks_.all_values().data();
  for (HalfarcId h : sorted_outgoing_[walk.node]) {
    if (h == reversal) continue;
    const int32_t begin = static_cast<int32_t>(fan_entries_.size());
    const std::span<const HalfarcInBlock> entries = halfarc_blocks_[h];
    const int32_t offset = static_cast<int32_t>(entries.data() - all_entries);
    for (int32_t i = 0; i < static_cast<int32_t>(entries.size()); ++i) {
      if (in_fan_.Contains(entries[i].block)) fan_entries_.push_back(offset + i);
    }
    const int32_t end = static_cast<int32_t>(fan_entries_.size());
    if (end > begin) candidates_.push_back({h, begin, end});
  }
}

// Section 3.7, tests (a) node, (b) arc, (c) patch, in that order.
bool SeparationSearch::Impl::FindViolationDirs(const Walk& walk, bool at_start_box,
                                               std::span<const int64_t> q, DirSet& dirs,
                                               SeparationTargetKind& kind, int32_t& target) const {
  const DirSet off_link = static_cast<DirSet>(~link_axis_);
  if (mesh_.node_critical(walk.node) && at_start_box) {
    dirs = walk.walked & off_link;
    kind = SeparationTargetKind::kNode;
    target = walk.node;
    return true;
  }

  const HalfarcInBlock* const all_entries = halfarc_blocks_.all_values().data();
  for (const Candidate& candidate : candidates_) {
    const ArcId arc = ArcOf(candidate.halfarc);
    if (!mesh_.arc_critical(arc)) continue;
    // The arc's axis is read in the first of its blocks in the fan, as in the reference.
    const HalfarcInBlock& entry = all_entries[fan_entries_[candidate.begin]];
    Dir along = fan_to_reference_[entry.block].Apply(entry.dir);
    const DirSet approach = walk.walked & off_link & static_cast<DirSet>(~AxisBits(AxisOf(along)));
    if ((approach & walk.monotone) == 0) continue;
    int64_t length = q[arc];
    if (length < 0) {
      length = -length;
      along = Opposite(along);
    }
    if (TouchesStartBox(SpannedBox(walk.x, AddAlong(walk.x, along, length)))) {
      dirs = approach;
      kind = SeparationTargetKind::kArc;
      target = arc;
      return true;
    }
  }

  for (const CriticalSide& side : critical_sides_[walk.node]) {
    const BlockId b = slots_.block_of(side.slot);
    if (!in_fan_.Contains(b)) continue;
    const Rotation to_reference = fan_to_reference_[b];
    const int normal = AxisOf(to_reference.Apply(MakeDir(side.normal_axis, false)));
    const DirSet approach = walk.walked & off_link & AxisBits(normal);
    if ((approach & walk.monotone) == 0) continue;
    if (at_start_box || TouchesStartBox(PatchBox(walk, side.side, side.slot, to_reference))) {
      dirs = approach;
      kind = SeparationTargetKind::kPatch;
      target = PatchOf(side.side);
      return true;
    }
  }
  return false;
}

// Section 3.6: the block, placed in the reference frame with the walk's node at x, touches the
// start box. The reference forms the interval from the (-,-,-) and (+,+,+) corners without
// sorting and rejects it when inverted. The answer depends on the block and the node only, so it
// is computed once per block and pop.
bool SeparationSearch::Impl::Admissible(const Walk& walk, bool at_start_box, BlockId block) {
  if (fan_admissible_[block] >= 0) return fan_admissible_[block] != 0;
  // Without negative arcs every boundary node lies in its block's sorted box, so that box
  // contains the walk's position.
  if (at_start_box && negative_slack_ == 0 && options_.block_box == BlockBoxMode::kSorted) {
    fan_admissible_[block] = 1;
    return true;
  }
  const Rotation to_reference = fan_to_reference_[block];
  const IntVec3& at = positions_[fan_slot_[block]];
  const IntVec3 low = Add(
      walk.x, to_reference.Apply(Subtract(positions_[slots_.corner_slot(block, kMinCorner)], at)));
  const IntVec3 high = Add(
      walk.x, to_reference.Apply(Subtract(positions_[slots_.corner_slot(block, kMaxCorner)], at)));
  const IntBox block_box =
      options_.block_box == BlockBoxMode::kSorted ? SpannedBox(low, high) : IntBox{low, high};
  const bool admissible = TouchesStartBox(block_box);
  fan_admissible_[block] = admissible ? 1 : 0;
  return admissible;
}

// Section 3.9: at most one successor per candidate halfarc, through the first block (in radial
// order) that is admissible and gives an allowed step.
void SeparationSearch::Impl::Expand(int32_t walk_index, bool at_start_box,
                                    std::span<const int64_t> q) {
  const Walk walk = arena_[walk_index];
  const HalfarcInBlock* const all_entries = halfarc_blocks_.all_values().data();
  for (const Candidate& candidate : candidates_) {
    const HalfarcId h = candidate.halfarc;
    const ArcId arc = ArcOf(h);
    const NodeId head = mesh_.head(h);
    if (walk.branched && seen_post_.Contains(head)) continue;
    for (int32_t i = candidate.begin; i < candidate.end; ++i) {
      const HalfarcInBlock& entry = all_entries[fan_entries_[i]];
      if (!Admissible(walk, at_start_box, entry.block)) continue;
      const Dir dir = fan_to_reference_[entry.block].Apply(entry.dir);
      const DirSet dir_bit = DirBit(dir);
      const bool along_link = (dir_bit & link_axis_) != 0;
      Walk next = walk;
      if (!walk.branched && !along_link) {
        // A pre-branch arc seen across the link axis means this block's rotation is not the
        // one the link was set up with; another block of the same halfarc may fit.
        if (pre_branch_arcs_.Contains(arc)) continue;
        if (!branch_offs_.Contains(h)) continue;
        next.branched = true;
        next.monotone &= dir_bit;
      }
      if (next.branched) ++next.k;
      next.x = AddAlong(walk.x, dir, q[arc]);
      next.walked |= dir_bit;
      next.monotone &= static_cast<DirSet>(~DirBit(Opposite(dir)));
      if (next.monotone == 0) continue;  // walked against the monotone direction
      if (!along_link) next.cost += mesh_.arc_length(arc);
      next.parent = walk_index;
      next.step = h;
      next.node = head;
      next.slot = entry.head_slot;
      next.rotation = fan_rotation_[entry.block];
      next.step_dir = dir;
      if (next.branched) {
        // After branching M is exactly the monotone direction d. Every violation test needs
        // zero displacement along d's axis (section 3.7), steps against d are never taken, and
        // steps along d only move back through negative arcs, each at most once.
        const Dir monotone = static_cast<Dir>(__builtin_ctz(next.monotone));
        const int64_t ahead =
            IsNegative(monotone) ? -next.x[AxisOf(monotone)] : next.x[AxisOf(monotone)];
        next.hopeless = ahead > negative_slack_;
      }
      Push(next);
      break;
    }
  }
}

// Section 3.8: one-way axes contribute their arcs with +1 to both rows; an axis walked both ways
// contributes its signed net displacement to the default row, the side longer in target length
// positive (ties: the negative direction's arcs positive).
void SeparationSearch::Impl::BuildViolation(int config, int32_t walk_index, DirSet dirs,
                                            SeparationTargetKind kind, int32_t target,
                                            SeparationViolation& violation) {
  const SeparationStartConfiguration& c = configs_[config];
  violation.start_entity = c.entity;
  violation.sector = c.sector;
  violation.start_dim = c.is_link ? EntityDim::kLink : EntityDim::kNode;
  violation.start_node = c.start_node;
  violation.found_by = options_.block_box;
  violation.target_kind = kind;
  violation.target = target;

  violation.path.clear();
  for (std::vector<ArcId>& arcs : walked_arcs_) arcs.clear();
  for (int32_t i = walk_index; arena_[i].parent >= 0; i = arena_[i].parent) {
    const Walk& w = arena_[i];
    if (w.branched) violation.path.push_back(w.step);
    walked_arcs_[DirIndex(w.step_dir)].push_back(ArcOf(w.step));
  }
  std::reverse(violation.path.begin(), violation.path.end());
  for (std::vector<ArcId>& arcs : walked_arcs_) std::reverse(arcs.begin(), arcs.end());

  const auto target_length = [this](const std::vector<ArcId>& arcs) {
    double sum = 0;
    for (ArcId a : arcs) sum += mesh_.arc_length(a);
    return sum;
  };
  std::vector<ArcId> positive, negative, one_way;
  for (int axis = 0; axis < 3; ++axis) {
    const DirSet on_axis = dirs & AxisBits(axis);
    if (on_axis == 0) continue;
    if (on_axis == AxisBits(axis)) {
      const std::vector<ArcId>& plus = walked_arcs_[DirIndex(MakeDir(axis, false))];
      const std::vector<ArcId>& minus = walked_arcs_[DirIndex(MakeDir(axis, true))];
      const bool plus_longer = target_length(plus) > target_length(minus);
      const std::vector<ArcId>& up = plus_longer ? plus : minus;
      const std::vector<ArcId>& down = plus_longer ? minus : plus;
      positive.insert(positive.end(), up.begin(), up.end());
      negative.insert(negative.end(), down.begin(), down.end());
    } else {
      const Dir d = MakeDir(axis, (on_axis & DirBit(MakeDir(axis, false))) == 0);
      const std::vector<ArcId>& arcs = walked_arcs_[DirIndex(d)];
      positive.insert(positive.end(), arcs.begin(), arcs.end());
      one_way.insert(one_way.end(), arcs.begin(), arcs.end());
    }
  }
  violation.default_row = SeparationRow{};
  violation.failsafe_row = SeparationRow{};
  for (ArcId a : positive) AddTerm(violation.default_row.terms, a, +1);
  for (ArcId a : negative) AddTerm(violation.default_row.terms, a, -1);
  for (ArcId a : one_way) AddTerm(violation.failsafe_row.terms, a, +1);
  DropZeroTerms(violation.default_row.terms);
  DropZeroTerms(violation.failsafe_row.terms);
}

SeparationSearch::SeparationSearch(const TMesh& mesh, SeparationSearchOptions options)
    : impl_(std::make_unique<Impl>(mesh, std::make_shared<SeparationSearchTables>(mesh), nullptr,
                                   options)) {}
SeparationSearch::SeparationSearch(const TMesh& mesh, const SeparationSearch& sharing_with,
                                   SeparationSearchOptions options)
    : impl_(std::make_unique<Impl>(mesh, sharing_with.impl_->tables(),
                                   sharing_with.impl_->scratch(), options)) {}
SeparationSearch::~SeparationSearch() = default;
SeparationSearch::SeparationSearch(SeparationSearch&&) noexcept = default;
SeparationSearch& SeparationSearch::operator=(SeparationSearch&&) noexcept = default;

std::vector<SeparationViolation> SeparationSearch::FindViolations(std::span<const int64_t> q) {
  std::vector<SeparationViolation> violations;
  impl_->FindViolations(q, [&](SeparationViolation& v) {
    violations.push_back(std::move(v));
    return true;
  });
  return violations;
}

int64_t SeparationSearch::FindViolations(std::span<const int64_t> q,
                                         const std::function<bool(SeparationViolation&)>& sink) {
  return impl_->FindViolations(q, sink);
}

}  // namespace ispq
