// Integer-Sheet-Pump quantization (Brueckler & Campen 2024, the paper in shared/paper): integer
// arc lengths q that are consistent, give no block a negative extent and are separating,
// minimizing d(q) = sum_a (q_a - s * l_a)^2 by a greedy sequence of small sheet LPs.
//
// This is the entry point used in-process by the CLI and by every server worker. One call runs
// on the calling thread only.
#ifndef ISPQ_CORE_QUANTIZER_H_
#define ISPQ_CORE_QUANTIZER_H_

#include <cstdint>
#include <limits>
#include <vector>

#include "absl/status/statusor.h"
#include "core/quantization_progress.h"
#include "core/separation_check.h"
#include "core/solve_interrupter.h"
#include "core/tmesh.h"

namespace ispq {

struct QuantizeOptions {
  double scaling = 1.0;              // s: targets are s * l_a; must be finite and > 0
  bool mixed_sign = true;            // paper section 4.3.3
  bool decompose = true;             // independent subproblems (paper section 4.4)
  bool per_arc_nonnegative = false;  // add q_a >= 0 for every arc to the block-extent rows
  // The searches the result must pass (core/separation_check.h); both unless reproducing upstream.
  SeparationRule separation = SeparationRule::kBothSearches;
  double time_limit_seconds = std::numeric_limits<double>::infinity();
};

enum class Termination : uint8_t {
  kConverged,    // no improving sheet left and the separation search finds nothing
  kTimeLimit,    // stopped at the time limit; q is the best valid result found, if any
  kInterrupted,  // stopped by the SolveInterrupter; likewise
};

const char* TerminationName(Termination termination);

struct QuantizeStats {
  int64_t lp_solves = 0;
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
  double greedy_seconds = 0;
  double separation_search_seconds = 0;
  double separating_update_seconds = 0;
  double solve_seconds = 0;  // the whole quantization, in-process, without reading the mesh
};

struct QuantizeResult {
  Termination termination = Termination::kConverged;
  // Whether q is valid (validator: consistent, non-negative extents, separating). False only
  // when a stop came before any valid q was reached; q is then the last iterate.
  bool valid = false;
  std::vector<int64_t> q;  // per arc, in the mesh's arc order
  double objective = 0;    // d(q, s*l)
  int64_t hexes = 0;       // only meaningful if valid
  QuantizeStats stats;
};

// INVALID_ARGUMENT naming the option or the limit if `options` cannot be used on `mesh`: a
// scaling that is not finite and > 0 or whose targets leave the representable range
// (core/quantization_limits.h), a negative or NaN time limit. Quantize checks this first;
// front ends call it to refuse a request before queuing it.
absl::Status ValidateQuantizeOptions(const TMesh& mesh, const QuantizeOptions& options);

// INVALID_ARGUMENT for bad options; INTERNAL if the LP solver fails unexpectedly.
// `observer` and `interrupter` may be null.
absl::StatusOr<QuantizeResult> Quantize(const TMesh& mesh, const QuantizeOptions& options,
                                        ProgressObserver* observer = nullptr,
                                        const SolveInterrupter* interrupter = nullptr);

}  // namespace ispq

#endif  // ISPQ_CORE_QUANTIZER_H_
