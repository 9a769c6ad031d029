// SPDX-License-Identifier: Apache-2.0
// The start configurations of a separation search that came back clean on the search's last q,
// and which of them need not run again on the next one (core/README.md, section Searches that
// remember clean starts).
//
// A search from one start configuration is a deterministic function of the q it reads, and it
// reads q only at the nodes it expands: the lengths of the arcs leaving such a node, and the
// positions of the blocks around it, which depend on the arcs of each block's spanning tree
// (core/block_node_positions.h). Link starts also read their link's arcs. Every node a search
// expands lies within as many arc hops of its start node as the walk took to reach it, and a
// link's arcs within the link's length: that bound is the search's reach. So when q changes, a
// node is dirty if it ends a changed arc or lies on a block whose positions read one, and a
// configuration that was clean before is still clean if no dirty node lies within its reach of its
// start node: one breadth-first search from the dirty nodes, up to the largest reach remembered,
// answers that for every configuration at once. The other input is the bound on how far negative
// arcs could bring a walk back (core/walk_slack.h): a clean search is kept with the bound it ran
// with, and stays clean under any bound sound for the new q that is no looser, since a walk
// hopeful under the tighter bound was hopeful under the old one, so the new search expands a
// prefix of the old one's walks and ends no later.
//
// What it saves depends on what moved between two calls: after a separating update most of a
// large part is unchanged (a 300k-arc part at level 100: 261k of 800k starts skipped, that search
// 11.8 -> 8.1 s), after a bulk descent, which moves bundles all over the part, almost nothing is.
#ifndef ISPQ_CORE_CLEAN_STARTS_H_
#define ISPQ_CORE_CLEAN_STARTS_H_

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "core/block_node_positions.h"
#include "core/tmesh.h"

namespace ispq {

class CleanStarts {
 public:
  // A configuration whose reach is above this is not remembered (its reach would not fit a byte;
  // such walks are rare and long, so the breadth-first search would cost what they save).
  static constexpr int kMaxReach = 254;

  // The mesh and slots must outlive this object.
  CleanStarts(const TMesh& mesh, const BlockNodeSlots& slots, int num_configs);

  // The next search runs on q: afterwards the queries below answer for q. A configuration the
  // search runs must then be recorded (Record or Forget), and every one it does not reach
  // forgotten (ForgetFrom), before the next call.
  void StartSearch(std::span<const int64_t> q);

  // Whether configuration `config` (starting at `start_node`) came back clean on an earlier q and
  // nothing within its reach changed since.
  bool UnchangedSinceClean(int config, NodeId start_node) const {
    return reach_[config] != kUnknown && distance_[start_node] > reach_[config];
  }
  // Whether `along` (per axis of the start block, sound for the current q) lets walks get no
  // further ahead than the bound its clean search ran with. With UnchangedSinceClean, the search
  // on the current q would come back clean too.
  bool BoundNoLooser(int config, const std::array<int64_t, 3>& along) const {
    for (int axis = 0; axis < 3; ++axis) {
      if (along[axis] > bound_[config][axis]) return false;
    }
    return true;
  }
  // The configuration came back clean on the current q under the walk bound `along`, after
  // expanding nodes within `reach` arc hops of its start node (links: at least the link's length
  // in arcs).
  void RecordClean(int config, int reach, const std::array<int64_t, 3>& along);
  void Forget(int config) { reach_[config] = kUnknown; }
  // Forgets configurations `first` and above: the search stopped before them.
  void ForgetFrom(int first);

 private:
  static constexpr uint8_t kUnknown = 255;
  static constexpr uint8_t kFar = 255;

  // Marks changed arcs and returns whether any changed.
  bool MarkChangedArcs(std::span<const int64_t> q);
  // distance_[n] = arc hops from n to the nearest dirty node, kFar beyond the largest reach.
  void MeasureDistances();

  const TMesh& mesh_;
  const BlockNodeSlots& slots_;
  std::vector<uint8_t> reach_;  // per configuration: kUnknown, or the reach of its clean search
  // Per configuration, the walk bound of its clean search, capped (a lower bound is sound).
  std::vector<std::array<int32_t, 3>> bound_;
  std::vector<int64_t> last_q_;
  std::vector<uint8_t> arc_changed_;  // per arc, between last_q_ and the new q
  std::vector<uint8_t> distance_;     // per node
  std::vector<NodeId> frontier_, next_frontier_;
};

}  // namespace ispq

#endif  // ISPQ_CORE_CLEAN_STARTS_H_
