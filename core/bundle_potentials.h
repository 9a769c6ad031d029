// SPDX-License-Identifier: Apache-2.0
// Node potentials of a T-mesh whose consistent quantizations are exactly potential differences
// (core/README.md, section Sheet LPs as flows).
//
// Where the patch rotations carry every block's axes into three global axes with consistent signs
// (no singular arc turns them), every arc runs along one global axis k, and each node has a
// coordinate per axis. The nodes joined by arcs of the other two axes share their k-coordinate:
// those groups are the axis-k potentials, and an arc's q is the difference of the potentials of
// its ends (head minus tail, in the axis's positive direction). Every such q is consistent (each
// consistency row sums q along two sides of a patch between the same two potentials), and where
// the part has no handle (first Betti number 0) every consistent q is such a difference: every
// cycle of arcs bounds patches, whose rows make its displacement zero. So a problem over
// consistent q becomes a problem over potentials with the consistency rows gone, which is what
// turns the bulk descent's LP into a min-cost flow (core/isp/sheet_network.h). Where the part has
// handles (through holes), the two sides of a hole may differ in length under consistency alone:
// such q are no differences, so a problem over potentials is a restriction there (has_handles()).
//
// Compute() checks all of this and returns nothing if any of it fails: frames that are not
// global, arcs of one bundle between different potentials, or a consistency row that the
// potentials do not satisfy identically (a check of the construction itself). Handles are counted
// by the Betti number from the Euler characteristic of nodes, arcs, patches and blocks and the
// number of boundary shells.
#ifndef ISPQ_CORE_BUNDLE_POTENTIALS_H_
#define ISPQ_CORE_BUNDLE_POTENTIALS_H_

#include <cstdint>
#include <optional>
#include <vector>

#include "core/arc_bundles.h"
#include "core/consistency_matrix.h"
#include "core/disjoint_sets.h"
#include "core/tmesh.h"

namespace ispq {

// The blocks' six directions (element 6 * block + DirIndex) joined across interior patches by
// the patches' rotations, or nothing if some block finds two of its own directions joined (an
// axis turned into another, or into its own opposite): the frames are global exactly when this
// has a value. Parts that share no patch keep frames of their own.
std::optional<DisjointSets> GlobalBlockDirections(const TMesh& mesh);

class BundlePotentials {
 public:
  static std::optional<BundlePotentials> Compute(const TMesh& mesh,
                                                 const ConsistencyMatrix& consistency,
                                                 const ArcBundles& bundles);

  int num_potentials() const { return num_potentials_; }
  // q of every arc of bundle b is U[head(b)] - U[tail(b)].
  int32_t tail(BundleId b) const { return tail_[b]; }
  int32_t head(BundleId b) const { return head_[b]; }
  // Whether the part has handles: then some consistent q are no potential differences.
  bool has_handles() const { return has_handles_; }

 private:
  BundlePotentials() = default;

  int32_t num_potentials_ = 0;
  std::vector<int32_t> tail_, head_;
  bool has_handles_ = false;
};

}  // namespace ispq

#endif  // ISPQ_CORE_BUNDLE_POTENTIALS_H_
