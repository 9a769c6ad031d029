// SPDX-License-Identifier: Apache-2.0
#include "core/separation_search.h"

#include <algorithm>
#include <limits>
#include <memory>
#include <optional>
#include <utility>

#include "core/block_node_positions.h"
#include "core/clean_starts.h"
#include "core/integer_box.h"
#include "core/invariant.h"
#include "core/linear_terms.h"
#include "core/separation_search_tables.h"
#include "core/separation_start_configurations.h"
#include "core/stamped_set.h"
#include "core/walk_slack.h"

namespace ispq {
namespace {

// One walk, stored once in an arena; its path is recovered through the parent links.
struct Walk {
  IntVec3 offset;  // position of `node` relative to the start node, in the reference frame
  double cost;     // target length walked off the link axis
  int32_t parent;  // arena index, -1 for the start
  HalfarcId step;  // the halfarc that led here, kNoId for the start
  NodeId node;
  SlotId slot;                    // (block used for the last step, node)
  int32_t steps_after_branching;  // halfarcs walked since the walk branched
  int32_t steps;                  // halfarcs walked since the start
  Rotation rotation;              // M: reference frame -> frame of the slot's block
  DirSet walked;                  // W
  DirSet monotone;                // M
  Dir step_dir;                   // direction of `step` in the reference frame
  bool branched;
  // Branched and already past the start box along the monotone direction by more than negative
  // arcs could ever bring back: neither this walk nor any walk extending it can report.
  bool hopeless;
};

struct QueueEntry {
  double cost;
  int32_t steps_after_branching;
  int32_t walk;
};

// The reference's heap order (a std::priority_queue over (length, path size)): the smallest
// (cost, steps_after_branching) on top, and among equal keys the heap's own layout decides. That is
// deterministic for a given sequence of pushes and pops, so with the same pushes in the same order
// ties pop exactly as in the reference, and rows can be compared with upstream's one for one
// (tests/differential). Both block-box modes use it, so they differ in admissibility only.
struct PopsLater {
  bool operator()(const QueueEntry& a, const QueueEntry& b) const {
    return a.cost > b.cost ||
           (a.cost == b.cost && a.steps_after_branching > b.steps_after_branching);
  }
};

// A candidate halfarc at the current node and its blocks in the fan (a range of fan_entries_).
struct Candidate {
  HalfarcId halfarc;
  int32_t begin;
  int32_t end;
};

}  // namespace

// The buffers of one call, sized by the mesh and rewritten by every call: nothing in them
// outlives a call, so the two searches of core/separation_check.h, which run one after the
// other on one thread, share one set. The geometry arrays are per slot and per halfpatch but a
// call fills only the blocks its fans reach: they are allocated without being written, so the
// pages of blocks no search reaches are never touched (a first touch costs about 12 us on the
// development VM, and a large run's first searches reach a small part of the mesh).
struct SeparationSearchScratch {
  explicit SeparationSearchScratch(const BlockNodeSlots& slots, const TMesh& mesh);

  std::unique_ptr<IntVec3[]> positions;  // per slot
  std::unique_ptr<IntBox[]> side_boxes;  // per halfpatch
  StampedSet geometry_ready;             // over blocks: positions and side boxes of geometry_q
  // The q of the geometry: the two searches of a check run on the same q, one after the other.
  std::vector<int64_t> geometry_q;
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
    : positions(new IntVec3[slots.num_slots()]),
      side_boxes(new IntBox[mesh.num_halfpatches()]),
      fan_rotation(mesh.num_blocks()),
      fan_to_reference(mesh.num_blocks()),
      fan_slot(mesh.num_blocks()),
      fan_admissible(mesh.num_blocks()) {
  geometry_ready.Resize(mesh.num_blocks());
  seen_pre.Resize(mesh.num_nodes());
  seen_post.Resize(mesh.num_nodes());
  branch_offs.Resize(mesh.num_halfarcs());
  pre_branch_arcs.Resize(mesh.num_arcs());
  in_fan.Resize(mesh.num_blocks());
}

class SeparationSearch::Impl {
 public:
  Impl(const TMesh& mesh, std::shared_ptr<SeparationSearchTables> tables,
       std::shared_ptr<SeparationSearchScratch> scratch, SeparationSearchOptions options);
  const std::shared_ptr<SeparationSearchTables>& tables() const { return tables_; }
  const std::shared_ptr<SeparationSearchScratch>& scratch() const { return scratch_; }

  int64_t FindViolations(std::span<const int64_t> q,
                         const std::function<bool(SeparationViolation&)>& sink);
  int64_t skipped_starts() const { return skipped_starts_; }
  int64_t settled_at_branch_offs() const { return settled_at_branch_offs_; }

 private:
  // What depends on q only: the positions of block b's slots and the boxes of the sides it owns
  // (core/README.md, section Tables and cost), computed the first time a fan reaches b on this q.
  void EnsureGeometry(BlockId b) {
    if (!geometry_ready_.Contains(b)) ComputeGeometry(b);
  }
  void ComputeGeometry(BlockId b);
  IntBox StartBox(int config, std::span<const int64_t> q) const;
  // How far negative arcs could bring a walk from `config` back along each axis of its start
  // block, into walk_bound_ (core/walk_slack.h).
  void BoundWalks(int config, std::span<const int64_t> q);
  // Whether `config` came back clean on an earlier call and its search on q would again
  // (core/clean_starts.h).
  bool StillClean(int config, std::span<const int64_t> q);

  // One search from `config`, whose start box is `start_box` (StartBox; core/README.md, section
  // Walks and their order); true and `violation` filled on the first hit, else the search's
  // reach is left in reach_ (core/clean_starts.h).
  bool Search(int config, const IntBox& start_box, std::span<const int64_t> q,
              SeparationViolation& violation);
  void Push(const Walk& walk);

  void BuildFan(const Walk& walk, bool at_start_box);
  void BuildCandidates(const Walk& walk);
  bool FindViolationDirs(const Walk& walk, bool at_start_box, std::span<const int64_t> q,
                         DirSet& dirs, SeparationTargetKind& kind, int32_t& target);
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
  // Mesh tables (core/README.md, section Tables and cost), shared and built as the searches read
  // them.
  const std::shared_ptr<SeparationSearchTables> tables_;
  const BlockNodeSlots& slots_;
  const SeparationStartConfigurations& configs_;

  // Buffers, possibly shared with another search of the mesh; the references name their parts.
  const std::shared_ptr<SeparationSearchScratch> scratch_;
  // Geometry of geometry_q_, the current call's q (core/README.md, section Integer positions),
  // valid for the blocks in geometry_ready_ (kept from the last call, of either search sharing the
  // buffers, if it had the same q).
  IntVec3* const positions_;  // per slot
  IntBox* const side_boxes_;  // per owned halfpatch side, in the owner's frame
  StampedSet& geometry_ready_;
  std::vector<int64_t>& geometry_q_;

  // State of the current search.
  IntBox box_{};
  DirSet link_axis_ = 0;
  std::vector<Walk>& arena_;
  std::vector<QueueEntry>& queue_;
  int hopeful_in_queue_ = 0;  // queued walks that are not hopeless
  // How far negative arcs could bring walks back (core/walk_slack.h): measured per call, and the
  // bound of the current start.
  WalkSlack walk_slack_;
  std::array<int64_t, 3> walk_bound_{};
  int reach_ = 0;                      // the most steps of an expanded walk (and the link's arcs)
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
  std::vector<int32_t>& fan_entries_;  // indices for SeparationSearchTables::HalfarcBlockAt
  std::array<std::vector<ArcId>, kNumDirs>& walked_arcs_;  // L[d] while building rows

  // The configurations that came back clean on the last call's q, this search's own.
  CleanStarts clean_starts_;
  int64_t skipped_starts_ = 0;
  int64_t settled_at_branch_offs_ = 0;
};

SeparationSearch::Impl::Impl(const TMesh& mesh, std::shared_ptr<SeparationSearchTables> tables,
                             std::shared_ptr<SeparationSearchScratch> scratch,
                             SeparationSearchOptions options)
    : mesh_(mesh),
      options_(options),
      tables_(std::move(tables)),
      slots_(tables_->slots()),
      configs_(tables_->configs()),
      scratch_(scratch != nullptr ? std::move(scratch)
                                  : std::make_shared<SeparationSearchScratch>(slots_, mesh)),
      positions_(scratch_->positions.get()),
      side_boxes_(scratch_->side_boxes.get()),
      geometry_ready_(scratch_->geometry_ready),
      geometry_q_(scratch_->geometry_q),
      arena_(scratch_->arena),
      queue_(scratch_->queue),
      walk_slack_(mesh, *tables_, options.prune_by_parallel_slack),
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
      walked_arcs_(scratch_->walked_arcs),
      clean_starts_(mesh, slots_, configs_.size()) {}

void SeparationSearch::Impl::ComputeGeometry(BlockId b) {
  geometry_ready_.Insert(b);
  slots_.ComputeBlockPositions(b, geometry_q_,
                               {positions_, static_cast<size_t>(slots_.num_slots())});
  for (const HalfpatchId hp : mesh_.block_halfpatches(b)) {
    if (mesh_.halfpatch_block(hp) != b) continue;  // another block's side
    const std::span<const SlotId> cycle = tables_->SideSlots(hp);
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

void SeparationSearch::Impl::BoundWalks(int config, std::span<const int64_t> q) {
  // Named: the FunctionRef below must not outlive it.
  const auto ensure = [this](BlockId b) { EnsureGeometry(b); };
  const PlacedGeometry geometry = {
      .ensure = ensure, .positions = positions_, .side_boxes = side_boxes_};
  walk_bound_ = walk_slack_.ForStart(config, q, box_, geometry);
}

int64_t SeparationSearch::Impl::FindViolations(
    std::span<const int64_t> q, const std::function<bool(SeparationViolation&)>& sink) {
  ISPQ_RELEASE_INVARIANT(static_cast<int>(q.size()) == mesh_.num_arcs(),
                         "the search is given one length per arc of its mesh");
  if (!std::equal(q.begin(), q.end(), geometry_q_.begin(), geometry_q_.end())) {
    geometry_q_.assign(q.begin(), q.end());
    geometry_ready_.Clear();
  }
  walk_slack_.Measure(q);
  clean_starts_.StartSearch(q);
  int64_t found = 0;
  SeparationViolation violation;
  for (int config = 0; config < configs_.size(); ++config) {
    if (StillClean(config, q)) {
      ++skipped_starts_;
      continue;
    }
    const IntBox start_box = StartBox(config, q);
    const std::optional<std::array<int64_t, 3>> settling =
        options_.prune_by_parallel_slack ? walk_slack_.BoundSettlingBranchOffs(config, q, start_box)
                                         : std::nullopt;
    if (settling.has_value()) {
      ++settled_at_branch_offs_;
      // A node start's walk would have expanded its start node alone (reach 0) and read the one
      // arc checked here. A link start's walk reads further along the link before it ends, so its
      // reach is unknown; its next call checks the branch-offs again, which is as cheap.
      if (configs_[config].is_link) {
        clean_starts_.Forget(config);
      } else {
        clean_starts_.RecordClean(config, 0, *settling);
      }
      continue;
    }
    if (!Search(config, start_box, q, violation)) {
      clean_starts_.RecordClean(config, reach_, walk_bound_);
      continue;
    }
    clean_starts_.Forget(config);
    ++found;
    if (!sink(violation)) {
      clean_starts_.ForgetFrom(config + 1);
      break;
    }
  }
  return found;
}

// The class bound needs no geometry; only when it grew past the one the clean search ran with is
// the start's own (local) bound measured, as its search would.
bool SeparationSearch::Impl::StillClean(int config, std::span<const int64_t> q) {
  if (!clean_starts_.UnchangedSinceClean(config, configs_[config].start_node)) return false;
  if (clean_starts_.BoundNoLooser(config, walk_slack_.ClassBound(config))) return true;
  if (!options_.prune_by_parallel_slack) return false;
  box_ = StartBox(config, q);
  if (IsInverted(box_)) return false;
  BoundWalks(config, q);
  return clean_starts_.BoundNoLooser(config, walk_bound_);
}

bool SeparationSearch::Impl::Search(int config, const IntBox& start_box, std::span<const int64_t> q,
                                    SeparationViolation& violation) {
  box_ = start_box;
  const SeparationStartConfiguration& c = configs_[config];
  reach_ = c.is_link ? static_cast<int>(mesh_.entity_halfarcs(c.entity).size()) : 0;
  walk_bound_ = {};  // set by BoundWalks; a start returned from before bounds no walk
  // A collapsed link (negative length, only while simple rows are violated) has an inverted
  // start box that nothing touches: no block is admissible and nothing can be reported.
  if (IsInverted(box_)) return false;
  link_axis_ = configs_.link_axis(config);
  BoundWalks(config, q);
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
  start.offset = {0, 0, 0};
  start.cost = 0;
  start.parent = -1;
  start.step = kNoId;
  start.node = configs_[config].start_node;
  start.slot = tables_->config_start_slot(config);
  start.steps_after_branching = 0;
  start.steps = 0;
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
    reach_ = std::max(reach_, walk.steps);

    // Every patch at the node contains the node, so while the walk's position lies in the start
    // box every patch box touches it and the fan may cross every patch.
    const bool at_start_box = TouchesStartBox(PointBox(walk.offset));
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
  queue_.push_back({walk.cost, walk.steps_after_branching, static_cast<int32_t>(arena_.size())});
  arena_.push_back(walk);
  std::push_heap(queue_.begin(), queue_.end(), PopsLater());
}

IntBox SeparationSearch::Impl::PatchBox(const Walk& walk, HalfpatchId side, SlotId slot,
                                        Rotation to_reference) const {
  const IntVec3& at = positions_[slot];
  const IntBox& own = side_boxes_[side];
  const IntBox local = RotateBox(to_reference, IntBox{Subtract(own.lo, at), Subtract(own.hi, at)});
  return {Add(walk.offset, local.lo), Add(walk.offset, local.hi)};
}

// core/README.md, section The fan: breadth-first over the blocks around the node, crossing a patch
// only if its rectangle touches the start box; each block keeps the rotation of its first route.
void SeparationSearch::Impl::BuildFan(const Walk& walk, bool at_start_box) {
  in_fan_.Clear();
  fan_order_.clear();
  const auto add = [this](BlockId b, Rotation rotation, SlotId slot) {
    EnsureGeometry(b);
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
    for (const FanCrossing& crossing : tables_->FanCrossings(slot)) {
      if (crossing.neighbor_slot == kNoId) continue;
      const BlockId across = slots_.block_of(crossing.neighbor_slot);
      if (in_fan_.Contains(across)) continue;
      if (!at_start_box &&
          !TouchesStartBox(PatchBox(walk, crossing.side, slot, fan_to_reference_[b]))) {
        continue;
      }
      add(across, mesh_.crossing_rotation(crossing.side).After(fan_rotation_[b]),
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
  for (HalfarcId h : tables_->SortedOutgoing(walk.node)) {
    if (h == reversal) continue;
    const int32_t begin = static_cast<int32_t>(fan_entries_.size());
    const std::span<const HalfarcInBlock> entries = tables_->HalfarcBlocks(h);
    const int32_t offset = tables_->HalfarcBlocksIndex(h);
    for (int32_t i = 0; i < static_cast<int32_t>(entries.size()); ++i) {
      if (in_fan_.Contains(entries[i].block)) fan_entries_.push_back(offset + i);
    }
    const int32_t end = static_cast<int32_t>(fan_entries_.size());
    if (end > begin) candidates_.push_back({h, begin, end});
  }
}

// core/README.md, section Violation tests: (a) node, (b) arc, (c) patch, in that order.
bool SeparationSearch::Impl::FindViolationDirs(const Walk& walk, bool at_start_box,
                                               std::span<const int64_t> q, DirSet& dirs,
                                               SeparationTargetKind& kind, int32_t& target) {
  const DirSet off_link = static_cast<DirSet>(~link_axis_);
  if (mesh_.node_critical(walk.node) && at_start_box) {
    dirs = walk.walked & off_link;
    kind = SeparationTargetKind::kNode;
    target = walk.node;
    return true;
  }

  for (const Candidate& candidate : candidates_) {
    const ArcId arc = ArcOf(candidate.halfarc);
    if (!mesh_.arc_critical(arc)) continue;
    // The arc's axis is read in the first of its blocks in the fan, as in the reference.
    const HalfarcInBlock& entry = tables_->HalfarcBlockAt(fan_entries_[candidate.begin]);
    Dir along = fan_to_reference_[entry.block].Apply(entry.dir);
    const DirSet approach = walk.walked & off_link & static_cast<DirSet>(~AxisBits(AxisOf(along)));
    if ((approach & walk.monotone) == 0) continue;
    int64_t length = q[arc];
    if (length < 0) {
      length = -length;
      along = Opposite(along);
    }
    if (TouchesStartBox(SpannedBox(walk.offset, AddAlong(walk.offset, along, length)))) {
      dirs = approach;
      kind = SeparationTargetKind::kArc;
      target = arc;
      return true;
    }
  }

  for (const CriticalSide& side : tables_->CriticalSides(walk.node)) {
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

// core/README.md, section Block admissibility and the two block-box modes: the block, placed in the
// reference frame with the walk's node at x, touches the start box. The reference forms the
// interval from the (-,-,-) and (+,+,+) corners without sorting and rejects it when inverted. The
// answer depends on the block and the node only, so it is computed once per block and pop.
bool SeparationSearch::Impl::Admissible(const Walk& walk, bool at_start_box, BlockId block) {
  if (fan_admissible_[block] >= 0) return fan_admissible_[block] != 0;
  // Without negative arcs every boundary node lies in its block's sorted box, so that box
  // contains the walk's position.
  if (at_start_box && walk_slack_.total() == 0 && options_.block_box == BlockBoxMode::kSorted) {
    fan_admissible_[block] = 1;
    return true;
  }
  const Rotation to_reference = fan_to_reference_[block];
  const IntVec3& at = positions_[fan_slot_[block]];
  const IntVec3 low =
      Add(walk.offset,
          to_reference.Apply(Subtract(positions_[slots_.corner_slot(block, kMinCorner)], at)));
  const IntVec3 high =
      Add(walk.offset,
          to_reference.Apply(Subtract(positions_[slots_.corner_slot(block, kMaxCorner)], at)));
  const IntBox block_box =
      options_.block_box == BlockBoxMode::kSorted ? SpannedBox(low, high) : IntBox{low, high};
  const bool admissible = TouchesStartBox(block_box);
  fan_admissible_[block] = admissible ? 1 : 0;
  return admissible;
}

// core/README.md, section Expansion: at most one successor per candidate halfarc, through the first
// block (in radial order) that is admissible and gives an allowed step.
void SeparationSearch::Impl::Expand(int32_t walk_index, bool at_start_box,
                                    std::span<const int64_t> q) {
  const Walk walk = arena_[walk_index];
  for (const Candidate& candidate : candidates_) {
    const HalfarcId h = candidate.halfarc;
    const ArcId arc = ArcOf(h);
    const NodeId head = mesh_.head(h);
    if (walk.branched && seen_post_.Contains(head)) continue;
    for (int32_t i = candidate.begin; i < candidate.end; ++i) {
      const HalfarcInBlock& entry = tables_->HalfarcBlockAt(fan_entries_[i]);
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
      if (next.branched) ++next.steps_after_branching;
      ++next.steps;
      next.offset = AddAlong(walk.offset, dir, q[arc]);
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
        // After branching M is exactly the monotone direction d. Every violation test needs zero
        // displacement along d's axis (core/README.md, section Violation tests), steps against d
        // are never taken, and steps along d only move back through negative arcs, each at most
        // once.
        const Dir monotone = static_cast<Dir>(__builtin_ctz(next.monotone));
        const int64_t ahead =
            IsNegative(monotone) ? -next.offset[AxisOf(monotone)] : next.offset[AxisOf(monotone)];
        next.hopeless = ahead > walk_bound_[AxisOf(monotone)];
      }
      Push(next);
      break;
    }
  }
}

// core/README.md, section Rows of a violation: one-way axes contribute their arcs with +1 to both
// rows; an axis walked both ways contributes its signed net displacement to the default row, the
// side longer in target length positive (ties: the negative direction's arcs positive).
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
  for (ArcId a : positive) violation.default_row.terms.push_back({a, +1});
  for (ArcId a : negative) violation.default_row.terms.push_back({a, -1});
  for (ArcId a : one_way) violation.failsafe_row.terms.push_back({a, +1});
  MergeRepeatedTerms(violation.default_row.terms);
  MergeRepeatedTerms(violation.failsafe_row.terms);
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

int64_t SeparationSearch::skipped_starts() const { return impl_->skipped_starts(); }
int64_t SeparationSearch::settled_at_branch_offs() const { return impl_->settled_at_branch_offs(); }

}  // namespace ispq
