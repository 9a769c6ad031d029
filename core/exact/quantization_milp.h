// SPDX-License-Identifier: Apache-2.0
// The quantization problem as a MILP over bundles, the model of the exact mode; relaxed, the LP
// of the lower bound.
//
// Given a feasible q, every optimal q has each bundle value in its window
// (core/exact/bundle_objective.h, core/exact/window_slacks.h). The model has one integer column x_b
// per bundle, bounded to that window, and the objective in epigraph form: a column z_b >= every
// secant of f_b inside the window, which makes sum_b z_b = d(q) exact at every integer point of the
// windows. Bundles whose window holds one or two integers need no z_b: f_b is constant or linear
// there and goes straight into the objective. The rows are those of QuantizationConstraints.
#ifndef ISPQ_CORE_EXACT_QUANTIZATION_MILP_H_
#define ISPQ_CORE_EXACT_QUANTIZATION_MILP_H_

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "absl/status/statusor.h"
#include "core/exact/bundle_objective.h"
#include "core/exact/milp_model.h"
#include "core/exact/quantization_constraints.h"

namespace ispq {

// A model larger than this many secant rows is refused: its objective bound is so far above the
// minimum that exact solving is hopeless anyway.
inline constexpr int64_t kMaxSecantRows = 2'000'000;

struct QuantizationMilp {
  MilpModel model;
  std::vector<int> x_column;  // per bundle
  std::vector<int> z_column;  // per bundle; -1 if the bundle has no epigraph column

  // Column values for bundle values x (z_b = f_b(x_b)), e.g. as an initial solution; nullopt if
  // some x_b lies outside its window.
  std::optional<std::vector<double>> ColumnsOf(const BundleObjectives& objectives,
                                               std::span<const int64_t> x) const;
  // The bundle values of a solution, rounded to the nearest integers.
  std::vector<int64_t> BundleValuesOf(std::span<const double> columns) const;
};

// Appends the rows of `constraints` (equalities = 0, inequalities >= rhs) over the columns
// x_column[b] of the bundles: shared by the MILP and the lower bound's lazy LP.
void AppendConstraintRows(const QuantizationConstraints& constraints, std::span<const int> x_column,
                          LpRowBatch& rows);

// Per bundle, the window holding every optimal q, given a known q (per-bundle values x; see
// core/exact/window_slacks.h), widened by a rounding margin so that x itself is always inside.
std::vector<IntegerWindow> ModelWindows(const BundleObjectives& objectives,
                                        const QuantizationConstraints& constraints,
                                        std::span<const int64_t> x);

// The model whose windows are ModelWindows(objectives, constraints, x). Fails with
// RESOURCE_EXHAUSTED if it would need more than kMaxSecantRows secants.
absl::StatusOr<QuantizationMilp> BuildQuantizationMilp(const BundleObjectives& objectives,
                                                       const QuantizationConstraints& constraints,
                                                       std::span<const int64_t> x);
// The model for every q with objective <= upper_bound (one global slack).
absl::StatusOr<QuantizationMilp> BuildQuantizationMilp(const BundleObjectives& objectives,
                                                       const QuantizationConstraints& constraints,
                                                       double upper_bound);

// The rows alone over free integer bundle columns, objective 0: its LP relaxation tells whether
// the rows admit any q at all.
MilpModel BuildFeasibilityModel(int num_bundles, const QuantizationConstraints& constraints);

}  // namespace ispq

#endif  // ISPQ_CORE_EXACT_QUANTIZATION_MILP_H_
