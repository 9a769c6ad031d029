// SPDX-License-Identifier: Apache-2.0
#include "core/quantizer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <vector>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "core/block_extents.h"
#include "core/exact/cbc_milp_solver.h"
#include "core/exact/exact_quantizer.h"
#include "core/exact/lower_bound.h"
#include "core/invariant.h"
#include "core/isp/dual_simplex_sheet_lp.h"
#include "core/isp/integer_sheet_pump.h"
#include "core/quantization_limits.h"
#include "core/quantization_objective.h"
#include "core/quantization_validator.h"
#include "core/run_clock.h"
#include "core/separation_check.h"
#include "core/status_macros.h"

namespace ispq {
namespace {

using Clock = RunClock::Clock;

// Exact mode after ISP: the best q of both and the exact mode's bound.
absl::Status RunExactMode(const TMesh& mesh, const QuantizeOptions& options,
                          Clock::time_point start, ProgressObserver* observer,
                          const SolveInterrupter* interrupter, QuantizeResult& result) {
  ScopedCpuSeconds timer(&result.stats.exact_seconds);
  RunClock clock(interrupter, options.time_limit_seconds, start);
  const std::unique_ptr<MilpSolver> solver = NewCbcMilpSolver();
  ISPQ_ASSIGN_OR_RETURN(ExactOutcome exact, RunExactQuantization(mesh, options, result.q, *solver,
                                                                 ExactTuning{}, observer, clock));
  result.termination = exact.termination;
  result.q = std::move(exact.q);
  result.lower_bound = exact.lower_bound;
  result.stats.milp_solves = exact.milp_solves;
  result.stats.milp_nodes = exact.milp_nodes;
  result.stats.milp_incumbents = exact.incumbents;
  result.separation_rows = std::move(exact.separation_rows);
  return absl::OkStatus();
}

// The validator's verdict on result.q, the objective and the hex count; INTERNAL when the
// algorithm's own view contradicts the validator.
absl::Status Certify(const TMesh& mesh, const QuantizeOptions& options, bool claims_separating,
                     SeparationCheck& separation, QuantizeResult& result) {
  // Every result is checked by the validator, independently of what the algorithm believes.
  ISPQ_INVARIANT(static_cast<int>(result.q.size()) == mesh.num_arcs(), "one length per arc");
  ValidationOptions validation;
  validation.separation = options.separation;
  if (options.per_arc_nonnegative) validation.per_arc_lower_bound = 0;
  ISPQ_ASSIGN_OR_RETURN(const ValidationReport report,
                        ValidateQuantization(mesh, result.q, validation, separation));
  if (!report.out_of_range.empty() || report.hexes_overflow) {
    // Never hand out a value that the API's int32 q or int64 hex count would wrap.
    return absl::InternalError(
        absl::StrCat("the quantization left the representable range: ", report.Describe(3)));
  }
  result.valid = report.valid();
  if (!result.valid && claims_separating) {
    return absl::InternalError(absl::StrCat(
        "the quantizer's final q passed its own separation checks but not the validator: ",
        report.Describe(5)));
  }
  if (!result.valid && result.termination == Termination::kConverged) {
    return absl::InternalError(
        absl::StrCat("the quantizer converged to an invalid q: ", report.Describe(5)));
  }
  result.objective = QuantizationObjective(mesh, result.q, options.scaling);
  result.hexes = result.valid ? *HexCount(mesh, result.q) : 0;
  return absl::OkStatus();
}

bool WantsIspBound(const TMesh& mesh, const QuantizeOptions& options) {
  switch (options.lower_bound) {
    case LowerBoundMode::kAlways:
      return true;
    case LowerBoundMode::kNever:
      return false;
    case LowerBoundMode::kAuto:
      return mesh.num_arcs() <= kAutoLowerBoundMaxArcs;
  }
  return false;
}

// The objective was summed arc by arc, the bound over bundles (and by the solver): the two may
// differ in the last bits. A proven optimum's bound is its objective; a bound above the objective
// by more than rounding is a defect to report, never a negative gap to hand out.
absl::Status ReconcileBound(QuantizeResult& result) {
  const double objective = result.objective;
  if (result.termination == Termination::kOptimal) {
    result.lower_bound = objective;
    return absl::OkStatus();
  }
  if (*result.lower_bound > objective + 1e-7 * (1 + std::abs(objective))) {
    return absl::InternalError(
        absl::StrCat("lower bound ", *result.lower_bound, " is above the objective ", objective));
  }
  result.lower_bound = std::min(*result.lower_bound, objective);
  return absl::OkStatus();
}

// The LP bound of an ISP result for the rows the engine ended with.
absl::Status AddIspBound(const TMesh& mesh, const QuantizeOptions& options,
                         std::span<const SeparationRow> rows, QuantizeResult& result) {
  ScopedCpuSeconds timer(&result.stats.lower_bound_seconds);
  const std::unique_ptr<MilpSolver> solver = NewCbcMilpSolver();
  ISPQ_ASSIGN_OR_RETURN(result.lower_bound,
                        ComputeLowerBound(mesh, options, result.q, rows, *solver));
  return absl::OkStatus();
}

}  // namespace

absl::Status ValidateQuantizeOptions(const TMesh& mesh, const QuantizeOptions& options) {
  if (!std::isfinite(options.scaling) || options.scaling <= 0) {
    return absl::InvalidArgumentError(
        absl::StrCat("scaling must be finite and > 0, got ", options.scaling));
  }
  if (std::isnan(options.time_limit_seconds) || options.time_limit_seconds < 0) {
    return absl::InvalidArgumentError(
        absl::StrCat("time_limit_seconds must be >= 0, got ", options.time_limit_seconds));
  }
  return CheckTargetsRepresentable(mesh, options.scaling);
}

absl::StatusOr<QuantizeResult> Quantize(const TMesh& mesh, const QuantizeOptions& requested,
                                        ProgressObserver* observer,
                                        const SolveInterrupter* interrupter) {
  const Clock::time_point start = Clock::now();
  ISPQ_RETURN_IF_ERROR(ValidateQuantizeOptions(mesh, requested));
  QuantizeOptions options = requested;
  const bool exact = options.method == QuantizationMethod::kExact;
  if (exact && std::isinf(options.time_limit_seconds)) {
    options.time_limit_seconds = kDefaultExactTimeLimitSeconds;
  }
  // One separation check for the run and the validator: its tables depend on the mesh alone
  // (building them again cost 2-8% of a 10k-arc run, up to 7% at 30k). The validator's searches
  // run afresh on q. The time limit counts from the start of this call, the check's build too.
  SeparationCheck separation(mesh, options.separation);
  RunClock clock(interrupter, options.time_limit_seconds, start);
  ISPQ_ASSIGN_OR_RETURN(IspOutcome outcome,
                        RunIntegerSheetPump(mesh, options, DualSimplexSheetLpFactory(), IspTuning{},
                                            observer, clock, separation));
  QuantizeResult result;
  result.termination = outcome.termination;
  result.q = std::move(outcome.q);
  result.stats = outcome.stats;
  result.separation_rows = std::move(outcome.separation_rows);
  // Exact mode needs a valid start; without one (the time ran out in ISP) ISP's answer stands.
  if (exact && outcome.separating && outcome.termination == Termination::kConverged) {
    ISPQ_RETURN_IF_ERROR(RunExactMode(mesh, options, start, observer, interrupter, result));
  }
  ISPQ_RETURN_IF_ERROR(Certify(mesh, options, outcome.separating, separation, result));
  // A row that the best q violates came after it (sufficient, not necessary: q may separate the
  // same entities another way); it is not part of the problem that q's bound is certified for.
  std::erase_if(result.separation_rows,
                [&](const SeparationRow& row) { return !row.IsSatisfiedBy(result.q); });
  // A stopped run returns at once: its bound would cost time nobody granted.
  const bool stopped = result.termination == Termination::kTimeLimit ||
                       result.termination == Termination::kInterrupted;
  if (!result.valid) {
    result.lower_bound.reset();
  } else if (!exact && !stopped && WantsIspBound(mesh, options)) {
    ISPQ_RETURN_IF_ERROR(AddIspBound(mesh, options, result.separation_rows, result));
  }
  if (result.lower_bound.has_value()) {
    ISPQ_RETURN_IF_ERROR(ReconcileBound(result));
    result.gap = RelativeGap(result.objective, *result.lower_bound);
  }
  result.stats.solve_seconds = RunClock::SecondsSince(start);
  return result;
}

}  // namespace ispq
