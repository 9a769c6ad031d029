// SPDX-License-Identifier: Apache-2.0
// The Integer-Sheet-Pump algorithm (paper Alg. 1-3, App. A-C) with the lazy separation loop
// (core/README.md, sections The ISP engine and The separation loop): q = 0, greedy descent by
// integer sheets rooted at the bundles furthest from their targets, then rounds of (simple rows |
// structural search) -> separating sheet updates -> greedy descent, until the search finds nothing
// and a final thorough greedy pass (both directions for every bundle; toward its target only on
// large subproblems) changes nothing. A search hands over only the rows of its first few violations
// in each subproblem; while it left some over, the search is repeated right after the separating
// update, before descending (core/isp/isp_tuning.h, max_new_rows_per_search). On large meshes a
// valid q traced from the parametrization's layers comes first (core/isp/layered_start.h): reported
// at once, and the result if the run finds no better valid q before it stops.
//
// Quantize() (core/quantizer.h) is the product entry point: it validates the options, supplies
// the LP back end and checks the final q with the validator. The engine is written against
// core/isp/sheet_lp.h only; its parts are the sheet step (core/isp/sheet_step.h), the greedy
// queue (core/isp/greedy_queue.h), the rows and their roles (core/isp/separation_rows.h) and the
// subproblems with their LPs (core/isp/subproblem_set.h).
#ifndef ISPQ_CORE_ISP_INTEGER_SHEET_PUMP_H_
#define ISPQ_CORE_ISP_INTEGER_SHEET_PUMP_H_

#include <cstdint>
#include <vector>

#include "absl/status/statusor.h"
#include "core/isp/isp_tuning.h"
#include "core/isp/sheet_lp.h"
#include "core/quantization_progress.h"
#include "core/quantize_options.h"
#include "core/quantize_result.h"
#include "core/run_clock.h"
#include "core/separation_check.h"
#include "core/separation_row.h"
#include "core/solve_interrupter.h"
#include "core/tmesh.h"

namespace ispq {

struct IspOutcome {
  Termination termination = Termination::kConverged;
  std::vector<int64_t> q;  // per arc
  // The driver's own verdict: the simple rows hold and its last search on q found nothing.
  bool separating = false;
  // The separation rows in force at the end (found paths, default or failsafe form) over arcs,
  // each bundle written as its first arc: the rows the result's lower bound is certified for.
  std::vector<SeparationRow> separation_rows;
  QuantizeStats stats;
};

// Options must already be validated (core/quantizer.h). `new_lp` makes the LP of each
// subproblem; `observer` and `interrupter` may be null.
absl::StatusOr<IspOutcome> RunIntegerSheetPump(const TMesh& mesh, const QuantizeOptions& options,
                                               const SheetLpFactory& new_lp,
                                               const IspTuning& tuning, ProgressObserver* observer,
                                               const SolveInterrupter* interrupter);

// The same on the caller's clock (options.time_limit_seconds and the interrupter are the
// clock's) and with the searches of `separation`, built for this mesh and options.separation
// (otherwise INVALID_ARGUMENT): core/quantizer.cc hands its validator the same check.
absl::StatusOr<IspOutcome> RunIntegerSheetPump(const TMesh& mesh, const QuantizeOptions& options,
                                               const SheetLpFactory& new_lp,
                                               const IspTuning& tuning, ProgressObserver* observer,
                                               RunClock& clock, SeparationCheck& separation);

}  // namespace ispq

#endif  // ISPQ_CORE_ISP_INTEGER_SHEET_PUMP_H_
