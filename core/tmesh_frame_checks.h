// SPDX-License-Identifier: Apache-2.0
// Rules about directions and coordinates in the blocks' (u, v, w) frames (proto/README.md, sections
// Block frames, Transitions, Patches and Blocks): every patch lies in a face of each of its blocks,
// its sides run along their stated directions in the reference block, and its transition maps one
// block's frame onto the other's; every block edge is a chain of arcs from corner to corner along
// its positive axis; and the nodes' block coordinates differ along each arc by exactly its length.
//
// TMeshBuilder runs these once the incidences hold (core/tmesh_incidence_checks.h), so that
// every arc of a patch can be looked up in its blocks. Failures are INVALID_ARGUMENT naming the
// patch or block.
#ifndef ISPQ_CORE_TMESH_FRAME_CHECKS_H_
#define ISPQ_CORE_TMESH_FRAME_CHECKS_H_

#include <cstdint>
#include <span>

#include "absl/status/status.h"
#include "core/flat_lists.h"
#include "core/tmesh.h"

namespace ispq {

// Per patch, in id order: its cycle lies in a face of each of its blocks and, seen from each,
// winds counterclockwise about the normal into that block (so a halfpatch faces its block and
// the patch is a rectangle, not a folded cycle); its sides run along their directions in the
// reference block; its transition maps directions in the first block to those in the second.
absl::Status CheckPatchFrames(const TMesh& mesh);

// edge_halfarcs: 12 lists per block (by edge code), the halfarcs of block_edge_arcs oriented
// along the edge's positive axis as the input gave them. edge_order: 12 codes per block, the
// order in which the input listed the edges and in which they are checked.
absl::Status CheckBlockEdgeChains(const TMesh& mesh, const FlatLists<HalfarcId>& edge_halfarcs,
                                  std::span<const int8_t> edge_order);

// uvw(to) - uvw(from) = length * dir for every arc of every block, up to length_tolerance
// relative to the largest coordinate involved (at least 1).
absl::Status CheckBlockCoordinates(const TMesh& mesh, double length_tolerance);

}  // namespace ispq

#endif  // ISPQ_CORE_TMESH_FRAME_CHECKS_H_
