// SPDX-License-Identifier: Apache-2.0
#include "core/exact/incumbent_checker.h"

#include <cmath>
#include <utility>

namespace ispq {

IncumbentChecker::IncumbentChecker(const TMesh& mesh, SeparationRule rule,
                                   const BundleObjectives& objectives,
                                   QuantizationConstraints& constraints, std::vector<int64_t> start)
    : objectives_(objectives),
      constraints_(constraints),
      separation_(mesh, rule),
      best_(std::move(start)),
      best_objective_(objectives.Objective(best_)) {
  seen_.insert(best_);
}

CandidateVerdict IncumbentChecker::Check(std::span<const int64_t> x) {
  if (!seen_.emplace(x.begin(), x.end()).second) return CandidateVerdict::kSeen;
  if (!constraints_.SatisfiesFixedRows(x)) return CandidateVerdict::kNotFeasible;
  ++checked_;
  const std::vector<int64_t> q = constraints_.ArcValues(x);
  const std::vector<SeparationViolation> violations = separation_.FindFirstViolations(q);
  if (violations.empty()) {
    const double objective = objectives_.Objective(x);
    // Ties within rounding keep the earlier q (ISP's, if nothing else beat it).
    if (objective >= best_objective_ - 1e-9 * (1 + std::abs(best_objective_))) {
      return CandidateVerdict::kValid;
    }
    best_.assign(x.begin(), x.end());
    best_objective_ = objective;
    return CandidateVerdict::kImproved;
  }
  for (const SeparationViolation& v : violations) {
    rows_added_ += constraints_.AddSeparationRow(v.default_row, v.failsafe_row) ? 1 : 0;
  }
  return CandidateVerdict::kSeparated;
}

}  // namespace ispq
