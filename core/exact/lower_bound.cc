// SPDX-License-Identifier: Apache-2.0
#include "core/exact/lower_bound.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include "absl/status/status.h"
#include "core/arc_bundles.h"
#include "core/consistency_matrix.h"
#include "core/exact/bundle_objective.h"
#include "core/exact/lazy_epigraph_lp.h"
#include "core/exact/quantization_constraints.h"
#include "core/exact/quantization_milp.h"
#include "core/status_macros.h"

namespace ispq {

absl::StatusOr<double> ComputeLowerBound(const TMesh& mesh, const QuantizeOptions& options,
                                         std::span<const int64_t> q,
                                         std::span<const SeparationRow> separation_rows,
                                         MilpSolver& solver) {
  const ConsistencyMatrix consistency(mesh);
  const ArcBundles bundles(mesh, consistency);
  const BundleObjectives objectives(mesh, bundles, options.scaling);
  QuantizationConstraints constraints(mesh, consistency, bundles, options.per_arc_nonnegative);
  for (const SeparationRow& row : separation_rows) {
    if (row.IsSatisfiedBy(q)) constraints.AddSeparationRow(row, std::nullopt);
  }
  const std::vector<int64_t> x = constraints.BundleValues(q);
  if (!constraints.SatisfiedBy(x)) {
    return absl::InvalidArgumentError(
        "a lower bound needs a consistent q satisfying the simple rows");
  }
  const double objective = objectives.Objective(x);
  const std::vector<IntegerWindow> windows = ModelWindows(objectives, constraints, x);
  const std::optional<double> lazy =
      SolveLazyEpigraphRelaxation(objectives, constraints, windows, x);
  if (lazy.has_value()) return std::min(objective, *lazy);
  // The sparse simplex could not finish: the full model on the general solver.
  ISPQ_ASSIGN_OR_RETURN(const QuantizationMilp milp,
                        BuildQuantizationMilp(objectives, constraints, x));
  ISPQ_ASSIGN_OR_RETURN(const LpResult relaxation, solver.SolveRelaxation(milp.model));
  // q itself is feasible, so an infeasible relaxation can only be numerical noise.
  if (relaxation.status != LpStatus::kOptimal) return objective;
  return std::min(objective, relaxation.objective);
}

double RelativeGap(double objective, double lower_bound) {
  const double difference = std::max(0.0, objective - lower_bound);
  if (difference <= 1e-9 * (1 + std::abs(objective))) return 0;
  return difference / objective;
}

}  // namespace ispq
