// SPDX-License-Identifier: Apache-2.0
// Exact mode: the quantization problem (paper eq. 1) solved to proven optimality by a MILP
// (core/exact/quantization_milp.h) in the lazy separation loop of BBC22 (paper section 3): solve,
// check the solution with the product's separation search, add the rows of what it finds (default
// form; the failsafe forms of App. B if the default rows admit no q at all), solve again, until a
// solve's optimum passes the search (core/README.md, section Exact mode).
//
// The loop starts from a valid q (the ISP result): it windows the model and is CBC's first
// incumbent, so the run is anytime from its first second. Every incumbent the solver finds is
// checked at once rather than only each solve's optimum: a valid one that improves is reported
// as the new best (ProgressEvent with q), an invalid one stops the solve (by default) so that its
// rows join the next one instead of wasting time proving an invalid q optimal. The separation
// rows start empty, as in the reference's IQP: ISP's rows stem from its own path and may exclude
// better quantizations.
//
// The result: the best valid q seen (never worse than the start), and a lower bound: no q that
// satisfies the consistency, simple and found separation rows is better (core/exact/lower_bound.h
// says what that certifies). OPTIMAL when the two meet within the solver's tolerance.
#ifndef ISPQ_CORE_EXACT_EXACT_QUANTIZER_H_
#define ISPQ_CORE_EXACT_EXACT_QUANTIZER_H_

#include <cstdint>
#include <span>
#include <vector>

#include "absl/status/statusor.h"
#include "core/exact/milp_solver.h"
#include "core/quantization_progress.h"
#include "core/quantize_options.h"
#include "core/quantize_result.h"
#include "core/run_clock.h"
#include "core/tmesh.h"

namespace ispq {

struct ExactTuning {
  // Stop a MILP solve at its first incumbent that fails the separation search, add its rows and
  // solve again (false: solve each MILP to optimality first, as BBC22 describe).
  bool restart_at_invalid_incumbent = true;
  // Safety net against a loop that stops adding rows.
  int max_solves = 1000;
};

struct ExactOutcome {
  Termination termination = Termination::kConverged;  // kOptimal, or why it stopped
  std::vector<int64_t> q;                             // the best valid q, per arc
  double objective = 0;
  double lower_bound = 0;  // <= objective
  int64_t milp_solves = 0;
  int64_t milp_nodes = 0;
  int64_t incumbents = 0;  // candidates checked by the separation search
  // The separation rows of the last MILP, over arcs: those the lower bound is proven for.
  std::vector<SeparationRow> separation_rows;
};

// `start` must be a valid q (consistent, simple rows, separating). `clock` bounds the run;
// `observer` may be null. INTERNAL if the solver fails.
absl::StatusOr<ExactOutcome> RunExactQuantization(const TMesh& mesh, const QuantizeOptions& options,
                                                  std::span<const int64_t> start,
                                                  MilpSolver& solver, const ExactTuning& tuning,
                                                  ProgressObserver* observer, RunClock& clock);

}  // namespace ispq

#endif  // ISPQ_CORE_EXACT_EXACT_QUANTIZER_H_
