// SPDX-License-Identifier: Apache-2.0
#include "core/walk_slack.h"

#include <algorithm>
#include <limits>

#include "core/block_node_positions.h"
#include "core/invariant.h"
#include "core/parallel_classes.h"

namespace ispq {

WalkSlack::WalkSlack(const TMesh& mesh, SeparationSearchTables& tables, bool per_class)
    : mesh_(mesh), tables_(tables), per_class_(per_class) {}

void WalkSlack::Measure(std::span<const int64_t> q) {
  const ParallelClasses& classes = tables_.parallel_classes();
  class_slack_.assign(per_class_ ? classes.num_classes() : 1, 0);
  total_ = 0;
  negative_arc_blocks_.clear();
  local_entity_ = kNoId;
  for (ArcId a = 0; a < static_cast<ArcId>(q.size()); ++a) {
    if (q[a] >= 0) continue;
    total_ -= q[a];
    if (!per_class_) {
      class_slack_[0] -= q[a];
      continue;
    }
    class_slack_[classes.of_arc(a)] -= q[a];
    for (const HalfarcInBlock& entry : tables_.HalfarcBlocks(HalfarcOf(a, false))) {
      negative_arc_blocks_.push_back({entry.block, a});
    }
  }
  std::sort(negative_arc_blocks_.begin(), negative_arc_blocks_.end());
  MeasureNegativeBlockBoxes(q);
}

void WalkSlack::MeasureNegativeBlockBoxes(std::span<const int64_t> q) {
  scan_negative_blocks_ = false;
  negative_block_boxes_.clear();
  negative_blocks_.clear();
  for (const auto& [block, arc] : negative_arc_blocks_) {
    if (!negative_blocks_.empty() && negative_blocks_.back() == block) continue;
    if (negative_blocks_.size() == kMaxScannedBlocks) return;
    negative_blocks_.push_back(block);
  }
  if (negative_blocks_.empty()) return;
  if (!frame_computed_) {
    frame_ = GlobalFrame::Compute(mesh_);
    frame_computed_ = true;
  }
  if (!frame_.has_value() || !frame_->NodeCoordinates(mesh_, q, coordinates_)) return;
  const BlockNodeSlots& slots = tables_.slots();
  for (const BlockId b : negative_blocks_) {
    negative_block_boxes_.push_back(
        SpannedBox(coordinates_[slots.node_of(slots.corner_slot(b, kMinCorner))],
                   coordinates_[slots.node_of(slots.corner_slot(b, kMaxCorner))]));
  }
  scan_negative_blocks_ = true;
}

// Every chart of a block is its placement in the global frame, seen from the start (core/
// global_frame.h), so a block whose global corner box misses the global start box is never one
// whose negative arcs MeasureLocal counts.
bool WalkSlack::NoNegativeBlockTouches(int config, const IntBox& start_box) const {
  for (int axis = 0; axis < 3; ++axis) {
    if (start_box.lo[axis] == std::numeric_limits<int64_t>::min() ||
        start_box.hi[axis] == std::numeric_limits<int64_t>::max()) {
      return false;  // a cyclic link's unbounded box
    }
  }
  const BlockId start_block = tables_.configs()[config].start_block;
  const IntVec3& at = coordinates_[tables_.slots().node_of(tables_.config_start_slot(config))];
  const IntBox turned = RotateBox(frame_->to_block(start_block).Inverse(), start_box);
  const IntBox global = {Add(at, turned.lo), Add(at, turned.hi)};
  return std::none_of(negative_block_boxes_.begin(), negative_block_boxes_.end(),
                      [&](const IntBox& box) { return Overlap(global, box); });
}

// The branch-off's arc has the class of the direction the walk takes through it: every block the
// walk steps in is reached from the start block through patches (core/parallel_classes.h).
bool WalkSlack::AheadAtEveryBranchOff(int config, std::span<const int64_t> q) const {
  const ParallelClasses& classes = tables_.parallel_classes();
  for (HalfarcId h : tables_.configs().branch_offs(config)) {
    if (q[ArcOf(h)] <= class_slack_[classes.of_arc(ArcOf(h))]) return false;
  }
  return true;
}

std::optional<std::array<int64_t, 3>> WalkSlack::BoundSettlingBranchOffs(
    int config, std::span<const int64_t> q, const IntBox& start_box) const {
  if (AheadAtEveryBranchOff(config, q)) return ClassBound(config);
  if (!scan_negative_blocks_ || IsInverted(start_box) ||
      !NoNegativeBlockTouches(config, start_box)) {
    return std::nullopt;
  }
  for (HalfarcId h : tables_.configs().branch_offs(config)) {
    if (q[ArcOf(h)] <= 0) return std::nullopt;
  }
  return std::array<int64_t, 3>{0, 0, 0};
}

std::array<int64_t, 3> WalkSlack::ClassBound(int config) const {
  if (!per_class_) return {total_, total_, total_};
  const BlockId start_block = tables_.configs()[config].start_block;
  std::array<int64_t, 3> along;
  for (int axis = 0; axis < 3; ++axis) {
    along[axis] = class_slack_[tables_.parallel_classes().of_block_axis(start_block, axis)];
  }
  return along;
}

std::array<int64_t, 3> WalkSlack::ForStart(int config, std::span<const int64_t> q,
                                           const IntBox& start_box,
                                           const PlacedGeometry& geometry) {
  if (!per_class_ || total_ == 0) return ClassBound(config);
  if (scan_negative_blocks_ && NoNegativeBlockTouches(config, start_box)) return {0, 0, 0};
  const SeparationStartConfiguration& c = tables_.configs()[config];
  if (local_entity_ != c.entity) MeasureLocal(config, q, start_box, geometry);
  const ParallelClasses& classes = tables_.parallel_classes();
  std::array<int64_t, 3> along;
  for (int axis = 0; axis < 3; ++axis) {
    along[axis] = local_class_slack_[classes.of_block_axis(c.start_block, axis)];
  }
  return along;
}

// Every block a walk steps in is admitted by a fan, and a fan reaches a block from the walk's
// block across patches whose boxes touch the start box (every patch at a node inside it does). So
// from the start block, placed as the search places it, crossing every owned side whose box
// touches the start box reaches every (block, chart) a fan can, and a step happens only in those
// whose sorted corner box touches the start box (the reference's unsorted box admits fewer).
// Only the negative arcs of those blocks can bring a walk back.
void WalkSlack::MeasureLocal(int config, std::span<const int64_t> q, const IntBox& start_box,
                             const PlacedGeometry& geometry) {
  constexpr size_t kMaxCharts = 64;  // beyond this, the class bound stands
  const BlockNodeSlots& slots = tables_.slots();
  const SeparationStartConfiguration& c = tables_.configs()[config];
  const ParallelClasses& classes = tables_.parallel_classes();
  const auto touches_start_box = [&](const IntBox& box) {
    return !IsInverted(box) && Overlap(start_box, box);
  };
  local_entity_ = c.entity;
  local_class_slack_.assign(class_slack_.size(), 0);
  local_negative_arcs_.clear();
  charts_.clear();
  geometry.ensure(c.start_block);
  const IntVec3& start = geometry.positions[tables_.config_start_slot(config)];
  charts_.push_back({c.start_block, Rotation(), {-start[0], -start[1], -start[2]}});
  for (size_t i = 0; i < charts_.size(); ++i) {
    if (charts_.size() > kMaxCharts) {
      local_class_slack_ = class_slack_;
      return;
    }
    const BlockChart chart = charts_[i];
    const BlockId b = chart.block;
    const Rotation to_reference = chart.to_block.Inverse();
    const auto place = [&](const IntVec3& p) { return Add(chart.origin, to_reference.Apply(p)); };
    const IntBox corners = SpannedBox(place(geometry.positions[slots.corner_slot(b, kMinCorner)]),
                                      place(geometry.positions[slots.corner_slot(b, kMaxCorner)]));
    if (touches_start_box(corners)) {
      auto it = std::lower_bound(negative_arc_blocks_.begin(), negative_arc_blocks_.end(),
                                 std::pair<BlockId, ArcId>{b, 0});
      for (; it != negative_arc_blocks_.end() && it->first == b; ++it) {
        const ArcId a = it->second;
        if (std::find(local_negative_arcs_.begin(), local_negative_arcs_.end(), a) !=
            local_negative_arcs_.end()) {
          continue;
        }
        local_negative_arcs_.push_back(a);
        local_class_slack_[classes.of_arc(a)] -= q[a];
      }
    }
    for (const HalfpatchId side : mesh_.block_halfpatches(b)) {
      if (mesh_.halfpatch_block(side) != b) continue;  // another block's side
      const BlockId across = mesh_.halfpatch_block(side ^ 1);
      if (across == kNoId) continue;
      const IntBox& box = geometry.side_boxes[side];
      if (!touches_start_box(SpannedBox(place(box.lo), place(box.hi)))) continue;
      const SlotId anchor = tables_.SideSlots(side).front();
      const SlotId anchor_across = slots.Find(across, slots.node_of(anchor));
      ISPQ_INVARIANT(anchor_across != kNoId, "a patch's nodes lie on both of its blocks");
      geometry.ensure(across);
      const Rotation to_across = mesh_.crossing_rotation(side).After(chart.to_block);
      const IntVec3 origin = Subtract(place(geometry.positions[anchor]),
                                      to_across.Inverse().Apply(geometry.positions[anchor_across]));
      const bool known = std::any_of(charts_.begin(), charts_.end(), [&](const BlockChart& other) {
        return other.block == across && other.to_block == to_across && other.origin == origin;
      });
      if (!known) charts_.push_back({across, to_across, origin});
    }
  }
}

}  // namespace ispq
