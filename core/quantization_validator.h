// SPDX-License-Identifier: Apache-2.0
// The validator of proto/README.md, section Valid quantizations: given any T-mesh and any integer
// q, reports every consistency violation, every negative block extent, every violated simple row
// and the separation violations found by the searches, each with the offending element ids. Every
// result the product returns goes through it (its verdict is the result's `valid`), and tests
// call it on every result they produce.
#ifndef ISPQ_CORE_QUANTIZATION_VALIDATOR_H_
#define ISPQ_CORE_QUANTIZATION_VALIDATOR_H_

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "core/separation_check.h"
#include "core/separation_search.h"
#include "core/simple_constraints.h"
#include "core/tmesh.h"

namespace ispq {

struct ConsistencyViolation {
  PatchId patch;
  int axis;
  int64_t difference;  // sum along +axis minus sum along -axis
};

struct ValidationOptions {
  // Which searches must find nothing (core/separation_check.h); the default is the product's.
  SeparationRule separation = SeparationRule::kBothSearches;
  // If set, also require q_a >= this bound for every arc (the per-arc non-negativity switch).
  std::optional<int64_t> per_arc_lower_bound;
};

struct ValidationReport {
  // Arcs whose |q_a| exceeds kMaxArcLength (core/quantization_limits.h). When there are any,
  // nothing else is checked: sums over such values may not be representable.
  std::vector<ArcId> out_of_range;
  // The hex count does not fit int64 (checked only for a q that is otherwise valid).
  bool hexes_overflow = false;
  std::vector<ConsistencyViolation> consistency;
  std::vector<SimpleRow> simple;  // violated simple rows (negative extents, collapsed links...)
  // Left-hand side of each violated simple row at q (parallel to `simple`).
  std::vector<int64_t> simple_values;
  // Filled only when q is consistent and satisfies the simple rows (the search needs both):
  // the violations of every search of the rule.
  std::vector<SeparationViolation> separation;
  bool separation_checked = false;

  bool consistent() const { return consistency.empty(); }
  bool valid() const {
    return out_of_range.empty() && !hexes_overflow && consistency.empty() && simple.empty() &&
           separation_checked && separation.empty();
  }
  // One line per problem, naming the elements, at most max_lines lines.
  std::string Describe(int max_lines = 20) const;
};

// q.size() must equal mesh.num_arcs(); otherwise INVALID_ARGUMENT.
absl::StatusOr<ValidationReport> ValidateQuantization(const TMesh& mesh, std::span<const int64_t> q,
                                                      const ValidationOptions& options = {});

// The same with the searches of `separation`, which must have been built for this mesh and
// options.separation (otherwise INVALID_ARGUMENT): a caller that holds one saves building
// another (2-8% of a 10k-arc run). Nothing of an earlier use carries over: the check's tables
// depend on the mesh alone, and its searches run afresh on q.
absl::StatusOr<ValidationReport> ValidateQuantization(const TMesh& mesh, std::span<const int64_t> q,
                                                      const ValidationOptions& options,
                                                      SeparationCheck& separation);

}  // namespace ispq

#endif  // ISPQ_CORE_QUANTIZATION_VALIDATOR_H_
