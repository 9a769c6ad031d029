// SPDX-License-Identifier: Apache-2.0
// The rules of proto/README.md (sections Top-level fields to Resolution levels and scaling) that
// one node, arc, block or resolution level satisfies on its own, and the element counts. Patches,
// with many more rules, have core/tmesh_patch_checks.h; how elements fit together is checked once
// all are known (core/tmesh_incidence_checks.h, core/tmesh_frame_checks.h,
// core/tmesh_criticality_checks.h).
//
// TMeshBuilder runs these as each element is added, so the first broken element in id order is
// the one reported. Failures are INVALID_ARGUMENT naming the element ("arc 6: length nan is not
// a positive finite number"); the messages are part of the API.
#ifndef ISPQ_CORE_TMESH_ELEMENT_CHECKS_H_
#define ISPQ_CORE_TMESH_ELEMENT_CHECKS_H_

#include <span>

#include "absl/status/status.h"
#include "core/tmesh.h"
#include "core/tmesh_input.h"

namespace ispq {

// At least one element of each kind, and few enough that halfarc and halfpatch ids fit int32.
absl::Status CheckSizes(const TMeshSizes& sizes);

absl::Status CheckNode(NodeId n, const NodeInput& node, const FeaturesPresent& present);

// No loop, a positive finite length, a singular mark in -4..4, criticality as the flags imply,
// and at least one patch.
absl::Status CheckArc(ArcId a, const ArcInput& arc, const FeaturesPresent& present);

// The block's arcs and nodeUvw (sorted by id here) name each arc and node once.
absl::Status CheckBlock(BlockId b, const BlockInput& block);

// A level is one of the format's percentages with the format's factor for these arc lengths.
absl::Status CheckLevel(int index, const Level& level, std::span<const double> arc_lengths);

}  // namespace ispq

#endif  // ISPQ_CORE_TMESH_ELEMENT_CHECKS_H_
