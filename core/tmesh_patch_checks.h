// SPDX-License-Identifier: Apache-2.0
// The rules of proto/README.md, section Patches, that one patch satisfies, given the nodes and arcs
// before it: its blocks and flags agree, a boundary patch has the identity transition, its cycle is
// a closed chain of at least 4 distinct arcs, its reference block is its first block, and its four
// sides are contiguous runs of the cycle in two opposite pairs whose continuous lengths match.
//
// TMeshBuilder runs this as each patch is added; the cycle's halfarc ids must be in range (the
// decoder's duty). How the patch lies in its blocks' frames is checked once the blocks are known
// (core/tmesh_frame_checks.h).
#ifndef ISPQ_CORE_TMESH_PATCH_CHECKS_H_
#define ISPQ_CORE_TMESH_PATCH_CHECKS_H_

#include "absl/status/status.h"
#include "core/tmesh.h"
#include "core/tmesh_input.h"

namespace ispq {

// INVALID_ARGUMENT naming patch p and the first rule it breaks. `mesh` has its nodes and arcs;
// side lengths may differ by length_tolerance relative to the longer one (at least 1).
absl::Status CheckPatch(PatchId p, const PatchInput& patch, const TMesh& mesh,
                        const FeaturesPresent& present, double length_tolerance);

}  // namespace ispq

#endif  // ISPQ_CORE_TMESH_PATCH_CHECKS_H_
