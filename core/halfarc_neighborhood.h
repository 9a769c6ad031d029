// SPDX-License-Identifier: Apache-2.0
// What surrounds a halfarc: the halfpatches and blocks around it in radial order, and its
// neighbours within a halfpatch's boundary cycle (proto/README.md, section Ids, halfarcs and
// halfpatches).
//
// The separation search iterates these in a fixed order because the order decides ties and the
// start block of a link search. TMesh stores the radial order for halfarc 2a only; for 2a + 1 it
// is that list reversed with every halfpatch flipped. These helpers are meant for precomputation
// (they allocate); hot loops read the flat tables built from them.
#ifndef ISPQ_CORE_HALFARC_NEIGHBORHOOD_H_
#define ISPQ_CORE_HALFARC_NEIGHBORHOOD_H_

#include <vector>

#include "core/tmesh.h"

namespace ispq {

// Halfpatches whose cycle contains h, in radial order around h.
std::vector<HalfpatchId> HalfpatchesAroundHalfarc(const TMesh& mesh, HalfarcId h);

// Blocks faced by those halfpatches, in the same order, boundary sides skipped, each once.
std::vector<BlockId> BlocksAroundHalfarc(const TMesh& mesh, HalfarcId h);
// The same into `blocks` (cleared first), for loops over every halfarc: no allocation once
// `blocks` has grown.
void BlocksAroundHalfarc(const TMesh& mesh, HalfarcId h, std::vector<BlockId>* blocks);

// Position of h in the cycle of halfpatch hp, or -1 if the cycle does not contain h.
int IndexInHalfpatchCycle(const TMesh& mesh, HalfpatchId hp, HalfarcId h);

// The halfarcs after and before h in the cycle of hp; h must be in that cycle.
HalfarcId NextInHalfpatch(const TMesh& mesh, HalfpatchId hp, HalfarcId h);
HalfarcId PrevInHalfpatch(const TMesh& mesh, HalfpatchId hp, HalfarcId h);

// The block owning halfpatch side hp, or the block across the patch if hp is a boundary side:
// the frame in which the side's halfarc directions are read.
BlockId FrameBlockOfHalfpatch(const TMesh& mesh, HalfpatchId hp);

}  // namespace ispq

#endif  // ISPQ_CORE_HALFARC_NEIGHBORHOOD_H_
