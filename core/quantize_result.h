// SPDX-License-Identifier: Apache-2.0
// What a quantization gives back: the integer arc lengths with their verdict, how the run ended,
// how far from optimal it is proven to be and what it cost. The ISP engine (core/isp/) and the
// exact mode (core/exact/) fill the statistics; the facade (core/quantizer.h) adds the
// validator's verdict, the objective, the lower bound and the hex count.
#ifndef ISPQ_CORE_QUANTIZE_RESULT_H_
#define ISPQ_CORE_QUANTIZE_RESULT_H_

#include <cstdint>
#include <optional>
#include <vector>

#include "core/separation_row.h"

namespace ispq {

enum class Termination : uint8_t {
  kConverged,    // no improving sheet left and the separation search finds nothing
  kTimeLimit,    // stopped at the time limit; q is the best valid result found, if any
  kInterrupted,  // stopped by the SolveInterrupter; likewise
  kOptimal,      // exact mode: proven optimal for the separation rows found (gap 0)
};

const char* TerminationName(Termination termination);

struct QuantizeStats {
  int64_t lp_solves = 0;
  // Of those, LPs without a root that a min-cost flow answered (core/isp/sheet_network.h).
  int64_t flow_solves = 0;
  // What the sheet LPs' back ends did in those solves: simplex pivots (and how many of them left
  // the objective where it was), refactorizations of the basis, and solves the sparse dual
  // simplex handed to CLP (core/isp/dual_simplex_sheet_lp.h), of which those it gave up as
  // stalled (SparseDualSimplexOptions::max_degenerate_pivots).
  int64_t lp_pivots = 0;
  int64_t lp_degenerate_pivots = 0;
  int64_t lp_refactorizations = 0;
  int64_t lp_fallback_solves = 0;
  int64_t lp_stalled_solves = 0;
  // Greedy checks answered by the sheet of another root (IspTuning::cover_min_bundles).
  int64_t covered_checks = 0;
  int64_t sheets_inflating = 0;
  int64_t sheets_deflating = 0;
  int64_t sheets_mixed = 0;
  int64_t separating_updates = 0;
  int64_t failsafe_updates = 0;
  // Least common denominators of rational LP solutions (paper Fig. 8).
  int64_t lcd_one = 0;
  int64_t lcd_two = 0;
  int64_t lcd_more = 0;
  int64_t separation_rounds = 0;
  int64_t separation_rows = 0;  // structural rows found in all rounds
  int32_t subproblems = 0;      // after merging through separation rows
  // CPU seconds of the solving thread in each phase.
  double greedy_seconds = 0;
  double separation_search_seconds = 0;
  double separating_update_seconds = 0;
  double lower_bound_seconds = 0;  // the LP of the lower bound (ISP mode)
  double layers_seconds = 0;       // tracing the layered start (IspTuning::layered_start_min_arcs)
  // Exact mode: MILP solves of the lazy loop, branch-and-bound nodes, incumbents checked by the
  // separation search, and the time after ISP.
  int64_t milp_solves = 0;
  int64_t milp_nodes = 0;
  int64_t milp_incumbents = 0;
  double exact_seconds = 0;
  double solve_seconds = 0;  // wall time of the whole quantization, without reading the mesh
};

struct QuantizeResult {
  Termination termination = Termination::kConverged;
  // Whether q is valid (validator: consistent, non-negative extents, separating). False only
  // when a stop came before any valid q was reached; q is then the last iterate.
  bool valid = false;
  std::vector<int64_t> q;  // per arc, in the mesh's arc order
  double objective = 0;    // d(q, s*l)
  // No q that is consistent, keeps block extents >= 0, satisfies the simple rows and the
  // separation rows the run found has a smaller objective (core/exact/lower_bound.h); and
  // lower_bound <= objective. Only for valid results, and in ISP mode only if asked.
  std::optional<double> lower_bound;
  std::optional<double> gap;  // (objective - lower_bound) / objective; 0 if both are 0
  // The separation rows (eq. 1c) the run ended with that q satisfies, over arcs, each bundle
  // written as its smallest arc: the rows the lower bound is certified for, and what a view
  // highlights as the critical entities the run had to keep apart.
  std::vector<SeparationRow> separation_rows;
  int64_t hexes = 0;  // only meaningful if valid
  QuantizeStats stats;
};

}  // namespace ispq

#endif  // ISPQ_CORE_QUANTIZE_RESULT_H_
