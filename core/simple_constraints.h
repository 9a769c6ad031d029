// SPDX-License-Identifier: Apache-2.0
// The simple rows of the separation problem (proto/README.md, sections Non-negativity and
// Separation): every critical link has positive length, no critical region collapses completely,
// every block has non-negative extent along each axis, and optionally every arc is >= a lower
// bound.
#ifndef ISPQ_CORE_SIMPLE_CONSTRAINTS_H_
#define ISPQ_CORE_SIMPLE_CONSTRAINTS_H_

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "core/separation_row.h"
#include "core/tmesh.h"

namespace ispq {

enum class SimpleRowKind : uint8_t { kArcLowerBound, kLink, kRegion, kBlockExtent };

struct SimpleRow {
  SimpleRowKind kind;
  int32_t element;  // arc id, entity id (link or region), or block id
  int axis;         // block extent rows only (0..2); -1 for the other kinds
  SeparationRow row;
};

// All simple rows, in the order: arc bounds (if per_arc_lower_bound), links, regions, blocks.
std::vector<SimpleRow> BuildSimpleRows(const TMesh& mesh,
                                       std::optional<int64_t> per_arc_lower_bound);

}  // namespace ispq

#endif  // ISPQ_CORE_SIMPLE_CONSTRAINTS_H_
