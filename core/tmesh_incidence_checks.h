// SPDX-License-Identifier: Apache-2.0
// Incidence rules (proto/README.md, sections Nodes, Arcs and Blocks): the lists by which elements
// name each other agree. A node lists exactly the halfarcs that start at it; an arc lists exactly
// the halfpatches whose cycles contain it; blocks, their faces and their patches name each other
// consistently; and the blocks around an arc are the blocks that list it.
//
// TMeshBuilder runs these once every element is in, in this order; CheckArcBlocks reads the
// arc -> blocks adjacency the builder derives before calling it. Failures are INVALID_ARGUMENT
// naming the element whose list is wrong.
#ifndef ISPQ_CORE_TMESH_INCIDENCE_CHECKS_H_
#define ISPQ_CORE_TMESH_INCIDENCE_CHECKS_H_

#include "absl/status/status.h"
#include "core/tmesh.h"

namespace ispq {

// Every halfarc is listed exactly once, as outgoing of its tail.
absl::Status CheckNodeArcIncidence(const TMesh& mesh);

// arc_halfpatches(a) is exactly the set of halfpatches whose cycle contains halfarc 2a.
absl::Status CheckArcPatchIncidence(const TMesh& mesh);

// A block's halfpatches face it, its faces list patches on that face of it, and every patch is
// listed by each of its blocks, as a halfpatch and on its face.
absl::Status CheckPatchBlockIncidence(const TMesh& mesh);

// arc_blocks(a), the blocks met around the arc, are the blocks whose arc lists contain it.
absl::Status CheckArcBlocks(const TMesh& mesh);

}  // namespace ispq

#endif  // ISPQ_CORE_TMESH_INCIDENCE_CHECKS_H_
