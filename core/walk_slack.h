// SPDX-License-Identifier: Apache-2.0
// How far the negative arcs of a q could bring a walk of the separation search back
// (core/separation_search.h). A walk further ahead along its monotone direction than that is
// hopeless: neither it nor any walk extending it can report, and a start whose every branch-off
// is that far ahead cannot report at all (core/README.md, section Hopeless walks). Three bounds,
// each sound, from loosest to sharpest:
//   - the whole mesh's negative lengths (the only one without per-class pruning);
//   - those of one parallel class (core/parallel_classes.h): a walk along d steps only through
//     arcs of d's class;
//   - the local slack of a start: only the negative arcs on the blocks a fan of its walks could
//     admit, found by placing blocks outward from the start block across the patches whose boxes
//     touch the start box.
// The search measures once per call and asks for each start's bound; the local slack is the same
// for every start of an entity, so it is computed once per entity and call. On a part with one
// frame (core/global_frame.h) and a q with few negative arcs, a start none of whose blocks'
// boxes touches is bounded by zero at the cost of those box tests, without placing any block.
#ifndef ISPQ_CORE_WALK_SLACK_H_
#define ISPQ_CORE_WALK_SLACK_H_

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "absl/functional/function_ref.h"
#include "core/global_frame.h"
#include "core/integer_box.h"
#include "core/rotation.h"
#include "core/separation_search_tables.h"
#include "core/tmesh.h"

namespace ispq {

// The search's integer geometry of the current q (core/README.md, section Integer positions),
// computed block by block: what the local slack places blocks with.
struct PlacedGeometry {
  absl::FunctionRef<void(BlockId)> ensure;  // computes block b's positions and side boxes
  const IntVec3* positions;                 // per slot, of the ensured blocks
  const IntBox* side_boxes;                 // per owned halfpatch side, in its owner's frame
};

class WalkSlack {
 public:
  // With `per_class` false there is one bound for every walk, the whole mesh's negative lengths
  // (SeparationSearchOptions::prune_by_parallel_slack off).
  WalkSlack(const TMesh& mesh, SeparationSearchTables& tables, bool per_class);

  // Sums q's negative lengths (per class) and lists the blocks around each negative arc. Once
  // per call of the search, before the bounds below.
  void Measure(std::span<const int64_t> q);
  // Sum of -q_a over the arcs with q_a < 0.
  int64_t total() const { return total_; }
  // The same sum per parallel class (one entry without per-class pruning).
  const std::vector<int64_t>& per_class() const { return class_slack_; }

  // Whether every walk from `config` is hopeless at its first step off the start entity: before
  // branching a walk moves along the link axis only, so the step through a branch-off puts it
  // exactly that arc's length ahead. Per-class pruning only.
  bool AheadAtEveryBranchOff(int config, std::span<const int64_t> q) const;
  // A bound under which every walk from `config` is hopeless at that first step, or nothing: the
  // class bound if AheadAtEveryBranchOff, else zero if no block around a negative arc touches the
  // start box `start_box` (see ForStart) and every branch-off is longer than zero.
  std::optional<std::array<int64_t, 3>> BoundSettlingBranchOffs(int config,
                                                                std::span<const int64_t> q,
                                                                const IntBox& start_box) const;

  // The class bound of the walks from `config`, per axis of its start block: its class's
  // negative lengths (without per-class pruning, the whole mesh's). Needs no geometry.
  std::array<int64_t, 3> ClassBound(int config) const;

  // The bound of the walks from `config` per axis of its start block, whose start box
  // `start_box` is not inverted: the local slack, at most the class bound.
  std::array<int64_t, 3> ForStart(int config, std::span<const int64_t> q, const IntBox& start_box,
                                  const PlacedGeometry& geometry);

 private:
  // A block placed in the reference frame: a point p of the block (in its own frame) lies at
  // origin + to_block^-1 p. Around a singular arc one block can be placed in several charts.
  struct BlockChart {
    BlockId block;
    Rotation to_block;
    IntVec3 origin;
  };

  // The global corner boxes of the blocks around q's negative arcs, where the part has one frame
  // and q global coordinates (core/global_frame.h), into negative_block_boxes_.
  void MeasureNegativeBlockBoxes(std::span<const int64_t> q);
  // Whether, on a q with global coordinates, no block around a negative arc touches the start
  // box of `config`: then no walk from it steps through a negative arc.
  bool NoNegativeBlockTouches(int config, const IntBox& start_box) const;
  // The negative lengths per class on the blocks any fan of a walk from `config` could admit,
  // into local_class_slack_.
  void MeasureLocal(int config, std::span<const int64_t> q, const IntBox& start_box,
                    const PlacedGeometry& geometry);

  const TMesh& mesh_;
  SeparationSearchTables& tables_;
  const bool per_class_;
  int64_t total_ = 0;
  std::vector<int64_t> class_slack_;
  // (block, negative arc) for every block around a negative arc, sorted.
  std::vector<std::pair<BlockId, ArcId>> negative_arc_blocks_;
  // The local class slack of local_entity_, and the closure and arcs that measured it.
  std::vector<int64_t> local_class_slack_;
  EntityId local_entity_ = kNoId;
  std::vector<BlockChart> charts_;
  std::vector<ArcId> local_negative_arcs_;
  // The part's one frame, computed on the first q with negative arcs (nothing without one), and
  // on the current q every node's coordinates in it and the corner boxes of the blocks around
  // negative arcs, if there are at most kMaxScannedBlocks of those (else none).
  static constexpr size_t kMaxScannedBlocks = 256;
  bool frame_computed_ = false;
  std::optional<GlobalFrame> frame_;
  std::vector<IntVec3> coordinates_;
  std::vector<BlockId> negative_blocks_;
  std::vector<IntBox> negative_block_boxes_;
  bool scan_negative_blocks_ = false;
};

}  // namespace ispq

#endif  // ISPQ_CORE_WALK_SLACK_H_
