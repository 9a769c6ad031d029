// SPDX-License-Identifier: Apache-2.0
#include "core/isp/dual_simplex_sheet_lp.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "absl/status/status.h"
#include "core/isp/clp_sheet_lp.h"

namespace ispq {
namespace {

// The fallback CLP model is made for one solve from scratch, which on a large part takes tens of
// thousands of pivots (the bulk descent's first LP: 46k at 100k arcs, 130k at 300k): refactorizing
// every 400 of them instead of every 100 took the greedy phase of the 300k-arc assembly from 99 to
// 44 s CPU at level 100 and 16 to 7 s at level 5, the same objectives (800: 5 s at level 5, but
// the separating updates' solves 1.4x slower). Its steepest edge weights start at one rather than
// computed (ClpSheetLpOptions::dual_pricing says what that saves).
constexpr ClpSheetLpOptions kFreshClp = {
    .factorization_frequency = 400, .dual_pricing = ClpDualPricing::kSteepestEdgeFromUnitWeights};

// Whether every point of the column box satisfies `row` of `simplex`: such a row can never bind,
// and a solver that is not given it finds the same optima. Most rows of a bulk descent's LP are
// such (unit moves cannot use up a row's slack: 111k of 200k rows at 300k arcs).
bool HoldsOnColumnBox(const SparseDualSimplex& simplex, int row) {
  const int n = simplex.num_columns();
  const auto starts = simplex.row_starts();
  double min_activity = 0, max_activity = 0;
  for (int32_t t = starts[row]; t < starts[row + 1]; ++t) {
    const double coef = simplex.row_coefs()[t];
    const int column = simplex.row_columns()[t];
    const double lower = simplex.lower(column), upper = simplex.upper(column);
    min_activity += coef * (coef > 0 ? lower : upper);
    max_activity += coef * (coef > 0 ? upper : lower);
  }
  // An infinite bound makes an infinite activity of the right sign (the coefficients are
  // non-zero), never NaN: the row is then kept unless its own bound is infinite too.
  return simplex.lower(n + row) <= min_activity && max_activity <= simplex.upper(n + row);
}

class DualSimplexSheetLp final : public SheetLp {
 public:
  DualSimplexSheetLp(int num_columns, const SparseDualSimplexOptions& options)
      : simplex_(num_columns, options) {}

  int num_columns() const override { return simplex_.num_columns(); }
  int num_rows() const override { return simplex_.num_rows(); }
  void SetObjectiveCoefficient(int column, double value) override {
    simplex_.SetObjectiveCoefficient(column, value);
  }
  void SetColumnBounds(int column, double lower, double upper) override {
    simplex_.SetColumnBounds(column, lower, upper);
  }
  void SetRowBounds(int row, double lower, double upper) override {
    simplex_.SetRowBounds(row, lower, upper);
  }
  void AddRows(const LpRowBatch& batch) override { simplex_.AddRows(batch); }

  absl::StatusOr<LpOutcome> Solve() override {
    used_fallback_ = false;
    if (simplex_.most_costs_changed() &&
        simplex_.num_columns() >= simplex_.options().new_objective_clp_min_columns) {
      return SolveWithClp();
    }
    switch (simplex_.Solve(PivotBudget(), WorkBudget())) {
      case SparseDualSimplex::Status::kOptimal:
        return LpOutcome::kOptimal;
      case SparseDualSimplex::Status::kInfeasible:
        return LpOutcome::kInfeasible;
      case SparseDualSimplex::Status::kStopped:
        return LpOutcome::kStopped;
      case SparseDualSimplex::Status::kFailed:
        break;
    }
    return SolveWithClp();
  }

  void SetStopCheck(LpStopCheck should_stop) override {
    simplex_.SetStopCheck(should_stop);
    should_stop_ = std::move(should_stop);
  }

  SheetLpCounters counters() const override {
    return {.pivots = simplex_.iterations() + fallback_pivots_,
            .degenerate_pivots = simplex_.degenerate_pivots(),
            .refactorizations = simplex_.refactorizations(),
            .fallback_solves = fallback_solves_,
            .stalled_solves = simplex_.stalled_solves()};
  }

  std::span<const double> column_values() const override {
    return used_fallback_ ? std::span<const double>(fallback_values_) : simplex_.column_values();
  }
  void AppendNonzeroColumns(std::vector<int32_t>* columns) const override {
    if (used_fallback_) {
      SheetLp::AppendNonzeroColumns(columns);
    } else {
      simplex_.AppendNonzeroColumns(columns);
    }
  }

 private:
  // A new objective (the switch of weight schemes, a separating update, a bulk step) sends the
  // dual simplex back to the slack basis. Most such solves take under m/10 pivots from there; the
  // ones that take more (separating updates: 23k pivots on 49k rows at 200k arcs) CLP solves from
  // scratch in about half the time, and on a large LP CLP gets them at once
  // (SparseDualSimplexOptions::new_objective_clp_min_columns). 0: the options' limit.
  int64_t PivotBudget() const {
    if (!simplex_.most_costs_changed()) return 0;
    const SparseDualSimplexOptions& options = simplex_.options();
    const double per_rows = options.new_objective_pivots_per_row * simplex_.num_rows();
    return std::max<int64_t>({1, options.new_objective_min_pivots, std::llround(per_rows)});
  }

  // A warm solve on a large LP can cost far more than CLP's solve from scratch: on the optimal
  // basis of a whole part its pivots are dense (at 10^6 arcs each touched most of the 500k rows,
  // 2-4 ms a pivot, against 0.16 ms for CLP's from the slack basis: one separating update took
  // 121k pivots and 274 s, CLP's solves from scratch of that LP 11-14 s). So a warm solve is given
  // a multiple of what CLP's last solve from scratch of this LP cost, estimated from its pivots
  // (deterministically: the same answer on any machine), and handed to CLP past it; at worst
  // that costs (factor + 1) times the cheaper of the two. 0: no budget.
  int64_t WorkBudget() const {
    const SparseDualSimplexOptions& options = simplex_.options();
    if (simplex_.most_costs_changed() || last_clp_pivots_ == 0 ||
        simplex_.num_columns() < options.warm_budget_min_columns) {
      return 0;
    }
    const double pivots = static_cast<double>(last_clp_pivots_);
    return std::max<int64_t>(1, std::llround(options.warm_budget_factor * pivots * pivots /
                                             options.clp_pivots_squared_per_work));
  }

  // The model as it stands, solved from scratch by CLP, without the rows that hold on the whole
  // column box (HoldsOnColumnBox). Leaving them out is what CLP's presolve did to these models,
  // and nearly all it did; without it the model is built once and not copied again, a bulk
  // descent's LP solves in the same pivots, and a separating update's in fewer (one such LP of a
  // 300k-arc assembly: 37k -> 21k pivots, 17 -> 5 s; the whole run at level 100: separating
  // updates 71 -> 38 s CPU, peak RSS 703 -> 629 MiB, the same objective).
  absl::StatusOr<LpOutcome> SolveWithClp() {
    used_fallback_ = true;
    ++fallback_solves_;
    const int n = simplex_.num_columns(), m = simplex_.num_rows();
    std::unique_ptr<SheetLp> clp = NewClpSheetLp(n, kFreshClp);
    clp->SetStopCheck(should_stop_);
    std::vector<int32_t> given_rows;  // CLP's row k is row given_rows[k] here
    {
      LpRowBatch rows;  // freed before the solve: CLP holds its own copy
      const auto starts = simplex_.row_starts();
      for (int i = 0; i < m; ++i) {
        if (HoldsOnColumnBox(simplex_, i)) continue;
        given_rows.push_back(i);
        rows.Add(simplex_.row_columns().subspan(starts[i], starts[i + 1] - starts[i]),
                 simplex_.row_coefs().subspan(starts[i], starts[i + 1] - starts[i]),
                 simplex_.lower(n + i), simplex_.upper(n + i));
      }
      clp->AddRows(rows);
    }
    for (int j = 0; j < n; ++j) {
      clp->SetObjectiveCoefficient(j, simplex_.objective(j));
      clp->SetColumnBounds(j, simplex_.lower(j), simplex_.upper(j));
    }
    absl::StatusOr<LpOutcome> outcome = clp->Solve();
    last_clp_pivots_ = clp->counters().pivots;
    fallback_pivots_ += clp->counters().pivots;
    if (outcome.ok() && *outcome == LpOutcome::kOptimal) {
      fallback_values_.assign(clp->column_values().begin(), clp->column_values().end());
      // The sparse simplex goes on from CLP's optimal basis, not from where its budget ran out
      // (or from the old objective's basis): the solves that follow, with a few rows or costs
      // changed, are warm again.
      // A row left out is slack at every point, so its logical is basic.
      std::vector<uint8_t> clp_basis;
      if (clp->AppendBasis(&clp_basis)) {
        std::vector<uint8_t> is_basic(clp_basis.begin(), clp_basis.begin() + n);
        is_basic.resize(n + m, 1);
        for (size_t k = 0; k < given_rows.size(); ++k)
          is_basic[n + given_rows[k]] = clp_basis[n + k];
        simplex_.AdoptBasis(is_basic, fallback_values_);
      }
    }
    return outcome;
  }

  SparseDualSimplex simplex_;
  LpStopCheck should_stop_;  // for the fallback CLP
  bool used_fallback_ = false;
  std::vector<double> fallback_values_;
  int64_t fallback_solves_ = 0;
  int64_t fallback_pivots_ = 0;
  int64_t last_clp_pivots_ = 0;  // of the last solve from scratch by CLP (WorkBudget)
};

}  // namespace

std::unique_ptr<SheetLp> NewDualSimplexSheetLp(int num_columns,
                                               const SparseDualSimplexOptions& options) {
  return std::make_unique<DualSimplexSheetLp>(num_columns, options);
}

SheetLpFactory DualSimplexSheetLpFactory(const SparseDualSimplexOptions& options) {
  return [options](int num_columns) { return NewDualSimplexSheetLp(num_columns, options); };
}

}  // namespace ispq
