// SPDX-License-Identifier: Apache-2.0
// One frame for a whole part, where there is one: every block's rotation from it and every node's
// integer coordinates in it on a given q.
//
// The separation search places blocks chart by chart, from the start block outward across
// patches (core/walk_slack.h, core/separation_search.h), because around a singular arc a block can
// be placed in several charts. On a part whose patch rotations carry every block's axes into one
// frame consistently (no singular arc turns them) and whose blocks are all reached across
// patches, and on a q that is a difference of node coordinates in that frame (always, unless a
// handle's period is not zero), every chart of a block is the same placement: the block's
// coordinates, seen from the start. Then whether a block can touch a start box is one box test in
// this frame, without placing the blocks in between: what lets the walk bound skip most of its
// local measurement when the q has a few negative arcs (core/README.md, section Hopeless walks).
#ifndef ISPQ_CORE_GLOBAL_FRAME_H_
#define ISPQ_CORE_GLOBAL_FRAME_H_

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "core/direction.h"
#include "core/integer_box.h"
#include "core/rotation.h"
#include "core/tmesh.h"

namespace ispq {

class GlobalFrame {
 public:
  // Nothing if some patch's rotation disagrees with the blocks' frames (a singular arc), some
  // arc runs along different global directions in two of its blocks, or some block is not
  // reached from block 0 across patches.
  static std::optional<GlobalFrame> Compute(const TMesh& mesh);

  // The rotation from the global frame into block b's (block 0's frame is the global one).
  Rotation to_block(BlockId b) const { return to_block_[b]; }

  // Every node's coordinates on q (node 0 at the origin), with every arc's q the difference of
  // its ends' coordinates along its global direction; false if q is no such difference.
  bool NodeCoordinates(const TMesh& mesh, std::span<const int64_t> q,
                       std::vector<IntVec3>& coordinates) const;

 private:
  GlobalFrame() = default;

  std::vector<Rotation> to_block_;  // per block
  std::vector<Dir> arc_dir_;        // per arc, the global direction of halfarc 2a
};

}  // namespace ispq

#endif  // ISPQ_CORE_GLOBAL_FRAME_H_
