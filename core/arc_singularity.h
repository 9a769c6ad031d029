// SPDX-License-Identifier: Apache-2.0
// Which arcs are singular, from the blocks around them (proto/README.md, section Arcs).
//
// Around an interior arc the blocks fill a full turn: each block contributes a quarter turn if
// the arc is one of its edges and a half turn if the arc lies inside one of its faces, and the
// arc is singular iff the total is not 4 quarter turns. On the boundary the blocks fill the
// interior dihedral angle and the arc is singular (a sharp edge) iff that is not 2 quarter
// turns. A file's `singular` mark says how far from regular the arc is; the loader checks that
// it is non-zero exactly for the arcs the blocks make singular, because criticality (and so the
// separation certificate) depends on it. The magnitude is not checked: where blocks are nearly
// degenerate upstream's mark, taken from the tet mesh, can differ from the count (MC3D's `hand`).
#ifndef ISPQ_CORE_ARC_SINGULARITY_H_
#define ISPQ_CORE_ARC_SINGULARITY_H_

#include <vector>

#include "core/tmesh.h"

namespace ispq {

// Per arc, the quarter turns of the blocks around it. Reads arc_blocks and block_edge_arcs.
std::vector<int> QuarterTurnsAroundArcs(const TMesh& mesh);

// Whether arc a lies on a boundary patch.
bool ArcOnBoundary(const TMesh& mesh, ArcId a);

// Singular by the blocks around it, given its quarter turns.
inline bool SingularByQuarterTurns(int quarter_turns, bool on_boundary) {
  return quarter_turns != (on_boundary ? 2 : 4);
}

}  // namespace ispq

#endif  // ISPQ_CORE_ARC_SINGULARITY_H_
