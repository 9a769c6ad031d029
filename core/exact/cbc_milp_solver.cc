// SPDX-License-Identifier: Apache-2.0
#include "core/exact/cbc_milp_solver.h"

#include <cmath>
#include <vector>

#include "CbcEventHandler.hpp"
#include "CbcHeuristicLocal.hpp"
#include "CbcHeuristicRINS.hpp"
#include "CbcModel.hpp"
#include "CbcStrategy.hpp"
#include "ClpSimplex.hpp"
#include "CoinFinite.hpp"
#include "CoinPackedMatrix.hpp"
#include "OsiClpSolverInterface.hpp"
#include "absl/status/status.h"
#include "absl/strings/str_cat.h"

namespace ispq {
namespace {

// COIN spells infinity as +-COIN_DBL_MAX.
double ToCoin(double bound) {
  if (std::isinf(bound)) return bound > 0 ? COIN_DBL_MAX : -COIN_DBL_MAX;
  return bound;
}

std::vector<double> ToCoin(const std::vector<double>& bounds) {
  std::vector<double> out(bounds.size());
  for (size_t i = 0; i < bounds.size(); ++i) out[i] = ToCoin(bounds[i]);
  return out;
}

// The rows as a row-ordered CoinPackedMatrix.
CoinPackedMatrix RowMatrix(const MilpModel& model) {
  const LpRowBatch& rows = model.rows;
  std::vector<int> lengths(rows.size());
  for (int r = 0; r < rows.size(); ++r) lengths[r] = rows.starts()[r + 1] - rows.starts()[r];
  const std::vector<CoinBigIndex> starts(rows.starts().begin(), rows.starts().end());
  return CoinPackedMatrix(false, model.num_columns(), rows.size(),
                          static_cast<CoinBigIndex>(rows.columns().size()), rows.coefs().data(),
                          rows.columns().data(), starts.data(), lengths.data());
}

void Load(const MilpModel& model, bool with_integers, OsiClpSolverInterface& solver) {
  solver.messageHandler()->setLogLevel(0);
  const std::vector<double> row_lower(model.rows.lower().begin(), model.rows.lower().end());
  const std::vector<double> row_upper(model.rows.upper().begin(), model.rows.upper().end());
  solver.loadProblem(RowMatrix(model), ToCoin(model.column_lower).data(),
                     ToCoin(model.column_upper).data(), model.objective.data(),
                     ToCoin(row_lower).data(), ToCoin(row_upper).data());
  if (!with_integers) return;
  for (int j = 0; j < model.num_columns(); ++j) {
    if (model.integer[j]) solver.setInteger(j);
  }
}

// Relays CBC's events to the callbacks of the top-level search (heuristics run sub-searches on
// other column sets; their events are ignored) and turns a callback's "stop" into CBC's.
class EventRelay : public CbcEventHandler {
 public:
  EventRelay(MilpCallbacks* callbacks, double offset, int num_columns)
      : callbacks_(callbacks), offset_(offset), num_columns_(num_columns) {}

  CbcAction event(CbcEvent which) override {
    if (model_ == nullptr || model_->parentModel() != nullptr ||
        model_->getNumCols() != num_columns_) {
      return noAction;
    }
    if (which == solution || which == heuristicSolution) {
      const double* x = model_->bestSolution();
      if (x != nullptr && !callbacks_->OnIncumbent({x, static_cast<size_t>(num_columns_)},
                                                   model_->getObjValue() + offset_)) {
        stop_ = true;
      }
    } else if (which == node || which == treeStatus) {
      if (!callbacks_->OnProgress(model_->getBestPossibleObjValue() + offset_,
                                  model_->getNodeCount())) {
        stop_ = true;
      }
    }
    return stop_ ? stop : noAction;
  }
  CbcEventHandler* clone() const override { return new EventRelay(*this); }

 private:
  MilpCallbacks* callbacks_;
  double offset_;
  int num_columns_;
  bool stop_ = false;
};

void Configure(const MilpModel& model, const MilpSolveOptions& options, CbcModel& cbc) {
  cbc.setLogLevel(0);
  cbc.messageHandler()->setLogLevel(0);
  cbc.solver()->messageHandler()->setLogLevel(0);
  CbcStrategyDefault strategy(1, 5, 5, 0);  // default cuts (root only), heuristics; no presolve
  cbc.setStrategy(strategy);
  CbcHeuristicRINS rins(cbc);
  cbc.addHeuristic(&rins);
  CbcHeuristicLocal local(cbc);
  cbc.addHeuristic(&local);
  cbc.setUseElapsedTime(true);
  if (std::isfinite(options.time_limit_seconds)) {
    cbc.setMaximumSeconds(std::max(0.0, options.time_limit_seconds));
  }
  cbc.setAllowableGap(options.absolute_gap);
  cbc.setAllowableFractionGap(options.relative_gap);
  cbc.setNumberThreads(0);
  if (std::isfinite(options.cutoff)) cbc.setCutoff(options.cutoff - model.objective_offset);
  if (options.initial_solution.has_value()) {
    const std::vector<double>& x = *options.initial_solution;
    double objective = 0;
    for (int j = 0; j < model.num_columns(); ++j) objective += model.objective[j] * x[j];
    cbc.setBestSolution(x.data(), model.num_columns(), objective, true);
  }
}

MilpResult ResultOf(const MilpModel& model, const MilpSolveOptions& options, CbcModel& cbc) {
  MilpResult result;
  result.nodes = cbc.getNodeCount();
  const double* best = cbc.bestSolution();
  const bool has_best = best != nullptr && cbc.getObjValue() < 1e30;
  if (has_best) {
    result.best.emplace(best, best + model.num_columns());
    result.best_objective = cbc.getObjValue() + model.objective_offset;
  }
  if (cbc.isProvenOptimal() && has_best) {
    result.status = MilpStatus::kOptimal;
    result.bound = result.best_objective;
  } else if (cbc.isProvenInfeasible()) {
    result.status = MilpStatus::kInfeasible;
    result.bound = options.cutoff;
  } else {
    result.status = MilpStatus::kStopped;
    result.bound = cbc.getBestPossibleObjValue() + model.objective_offset;
    if (result.bound < -1e29) result.bound = -std::numeric_limits<double>::infinity();
  }
  return result;
}

class CbcMilpSolver final : public MilpSolver {
 public:
  absl::StatusOr<MilpResult> Solve(const MilpModel& model, const MilpSolveOptions& options,
                                   MilpCallbacks& callbacks) override {
    OsiClpSolverInterface solver;
    Load(model, true, solver);
    CbcModel cbc(solver);
    Configure(model, options, cbc);
    EventRelay relay(&callbacks, model.objective_offset, model.num_columns());
    cbc.passInEventHandler(&relay);
    cbc.branchAndBound();
    if (cbc.isAbandoned()) {
      return absl::InternalError(absl::StrCat("CBC abandoned the search (numerical trouble) on ",
                                              model.rows.size(), " rows x ", model.num_columns(),
                                              " columns"));
    }
    return ResultOf(model, options, cbc);
  }

  absl::StatusOr<LpResult> SolveRelaxation(const MilpModel& model) override {
    OsiClpSolverInterface solver;
    Load(model, false, solver);
    ClpSimplex* clp = solver.getModelPtr();
    clp->setLogLevel(0);
    clp->dual();
    LpResult result;
    if (clp->status() == 1) return result;  // infeasible
    if (clp->status() != 0) {
      return absl::InternalError(absl::StrCat("CLP failed with status ", clp->status(),
                                              " on the LP relaxation (", model.rows.size(),
                                              " rows x ", model.num_columns(), " columns)"));
    }
    result.status = LpStatus::kOptimal;
    result.objective = clp->objectiveValue() + model.objective_offset;
    return result;
  }
};

}  // namespace

std::unique_ptr<MilpSolver> NewCbcMilpSolver() { return std::make_unique<CbcMilpSolver>(); }

}  // namespace ispq
