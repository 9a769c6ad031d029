// SPDX-License-Identifier: Apache-2.0
// The linear-program interface the integer-sheet LPs (paper App. A) are written against
// (core/README.md, sections Sheet LPs and LP back ends).
//
// The quantizer keeps one small LP per independent subproblem alive for the whole run and
// solves it hundreds of times, each time after changing a handful of numbers: objective
// weights of the bundles a sheet touched, the bounds of the two root columns, row bounds whose
// right-hand side depends on the current quantization, and appended separation rows. This
// interface therefore exposes exactly those incremental edits and a Solve() that is expected to
// warm-start from the previous basis, in the spirit of an incremental solver interface (model
// edits are pushed to the live solver instead of rebuilding it). Columns are fixed at creation;
// rows can only be appended. Implementations: core/isp/dual_simplex_sheet_lp.h (the sparse dual
// simplex of core/isp/sparse_dual_simplex.h, the default) and core/isp/clp_sheet_lp.h (COIN-OR
// CLP, its fallback).
#ifndef ISPQ_CORE_ISP_SHEET_LP_H_
#define ISPQ_CORE_ISP_SHEET_LP_H_

#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <span>
#include <vector>

#include "absl/status/statusor.h"
#include "core/lp_row_batch.h"

namespace ispq {

// kStopped: the stop check (SetStopCheck) held before the solve finished; the column values are
// then no answer.
enum class LpOutcome : uint8_t { kOptimal, kInfeasible, kStopped };

// Asked by a back end every few pivots of a solve; true ends the solve with kStopped. The time
// limit and the caller's interrupter must reach inside a solve: on a million-arc part a single
// sheet LP took 200k pivots and 14 minutes, seven times the job's time limit.
using LpStopCheck = std::function<bool()>;

// What a back end did since it was made, for the run's statistics (core/quantize_result.h).
struct SheetLpCounters {
  int64_t pivots = 0;
  int64_t degenerate_pivots = 0;  // pivots with a dual step of zero (the objective stood still)
  int64_t refactorizations = 0;
  int64_t fallback_solves = 0;  // solves a back end handed to another solver
  int64_t stalled_solves = 0;   // of those, solves given up after too many degenerate pivots

  SheetLpCounters& operator+=(const SheetLpCounters& other) {
    pivots += other.pivots;
    degenerate_pivots += other.degenerate_pivots;
    refactorizations += other.refactorizations;
    fallback_solves += other.fallback_solves;
    stalled_solves += other.stalled_solves;
    return *this;
  }
  friend SheetLpCounters operator-(SheetLpCounters a, const SheetLpCounters& b) {
    a.pivots -= b.pivots;
    a.degenerate_pivots -= b.degenerate_pivots;
    a.refactorizations -= b.refactorizations;
    a.fallback_solves -= b.fallback_solves;
    a.stalled_solves -= b.stalled_solves;
    return a;
  }
};

// A minimization LP over num_columns() columns that is edited in place between solves. New
// columns start with bounds [0, +inf) and objective coefficient 0.
class SheetLp {
 public:
  virtual ~SheetLp() = default;

  virtual int num_columns() const = 0;
  virtual int num_rows() const = 0;

  virtual void SetObjectiveCoefficient(int column, double value) = 0;
  virtual void SetColumnBounds(int column, double lower, double upper) = 0;
  virtual void SetRowBounds(int row, double lower, double upper) = 0;
  // Appends the rows of the batch; they get the ids num_rows() .. num_rows() + batch.size() - 1.
  virtual void AddRows(const LpRowBatch& batch) = 0;

  // Whether the engine should box the free columns at SheetLpContext::column_cap
  // (core/isp/sheet_subproblem.h): CLP's dual simplex needs it, the sparse dual simplex does not.
  virtual bool wants_column_cap() const { return false; }

  // Solves from the previous basis. kInfeasible when no column values satisfy the bounds and
  // rows, kStopped when the stop check held first; an error only when the solver fails
  // (numerical trouble, unboundedness).
  virtual absl::StatusOr<LpOutcome> Solve() = 0;
  // The check every later Solve() polls between pivots (none by default).
  virtual void SetStopCheck(LpStopCheck should_stop) = 0;
  // Column values of the last solve that returned kOptimal.
  virtual std::span<const double> column_values() const = 0;
  virtual SheetLpCounters counters() const { return {}; }
  // The basis of the last solve that returned kOptimal: appends a flag per column and then per row,
  // set where that variable (a row's: its activity) is basic; false if the back end cannot say.
  virtual bool AppendBasis(std::vector<uint8_t>* /*is_basic*/) const { return false; }
  // Appends the columns whose value in column_values() is non-zero, in any order (back ends that
  // track them answer without scanning every column).
  virtual void AppendNonzeroColumns(std::vector<int32_t>* columns) const {
    const std::span<const double> x = column_values();
    for (int j = 0; j < static_cast<int>(x.size()); ++j) {
      if (x[j] != 0) columns->push_back(j);
    }
  }
};

// Makes the LP of one subproblem with the given number of columns (the engine's only way to get a
// solver, so that back ends plug in without the engine naming them).
using SheetLpFactory = std::function<std::unique_ptr<SheetLp>(int num_columns)>;

}  // namespace ispq

#endif  // ISPQ_CORE_ISP_SHEET_LP_H_
