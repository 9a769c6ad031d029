// SPDX-License-Identifier: Apache-2.0
// The parallel classes of a T-mesh: which block axes a walk can carry into one another. A walk that
// moves from block to block through their shared patches carries its directions along by each
// patch's rotation, so the pairs (block, axis) joined across every interior patch by that rotation
// fall into classes, and the axis of an arc in any block around it lands in one class: the arc's.
// Without singular arcs (a polycube-like part) there are three classes, one per global axis;
// a rotation around a singular arc joins the classes it turns into one another.
//
// The separation search uses them to bound how far negative arcs can bring a walk back along its
// monotone direction (core/README.md, section Hopeless walks): only the negative arcs of that
// direction's class can, because a walk that starts in block b along axis t steps along t only
// through arcs of the class of (b, t).
#ifndef ISPQ_CORE_PARALLEL_CLASSES_H_
#define ISPQ_CORE_PARALLEL_CLASSES_H_

#include <cstdint>
#include <vector>

#include "core/tmesh.h"

namespace ispq {

class ParallelClasses {
 public:
  explicit ParallelClasses(const TMesh& mesh);

  // Classes are numbered 0 .. num_classes() - 1 by their smallest (block, axis) pair.
  int num_classes() const { return num_classes_; }
  int32_t of_block_axis(BlockId b, int axis) const { return of_block_axis_[3 * b + axis]; }
  int32_t of_arc(ArcId a) const { return of_arc_[a]; }

 private:
  int num_classes_ = 0;
  std::vector<int32_t> of_block_axis_;  // 3 per block
  std::vector<int32_t> of_arc_;
};

}  // namespace ispq

#endif  // ISPQ_CORE_PARALLEL_CLASSES_H_
