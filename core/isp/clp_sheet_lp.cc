// SPDX-License-Identifier: Apache-2.0
#include "core/isp/clp_sheet_lp.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <utility>
#include <vector>

#include "ClpDualRowSteepest.hpp"
#include "ClpEventHandler.hpp"
#include "ClpFactorization.hpp"
#include "ClpSimplex.hpp"
#include "CoinFinite.hpp"
#include "absl/status/status.h"
#include "absl/strings/str_cat.h"

namespace ispq {
namespace {

// CLP spells infinity as +-COIN_DBL_MAX.
double ToClp(double bound) {
  if (std::isinf(bound)) return bound > 0 ? COIN_DBL_MAX : -COIN_DBL_MAX;
  return bound;
}

// Ends CLP's simplex (status 5, "stopped by event handler") once the stop check holds, asked every
// kIterationsBetweenChecks iterations: CLP calls the handler after every iteration, and a clock
// read costs more than a pivot of the small LPs. The model runs a clone of the handler
// (passInEventHandler), and CLP may clone it again: the clones share the verdict, so that a check
// that held once stops them all without being asked again, and the owner can clear it.
class StopCheckHandler final : public ClpEventHandler {
 public:
  // `held` is the verdict the clones share; its owner clears it before each solve.
  StopCheckHandler(LpStopCheck should_stop, std::shared_ptr<bool> held)
      : should_stop_(std::move(should_stop)), held_(std::move(held)) {}

  int event(Event which) override {
    if (which != endOfIteration) return -1;
    if (*held_) return 0;
    if (++iterations_ % kIterationsBetweenChecks != 0) return -1;
    *held_ = should_stop_ && should_stop_();
    return *held_ ? 0 : -1;
  }
  ClpEventHandler* clone() const override { return new StopCheckHandler(*this); }

 private:
  static constexpr int64_t kIterationsBetweenChecks = 16;
  LpStopCheck should_stop_;
  std::shared_ptr<bool> held_;  // one per SetStopCheck, shared by the clones CLP makes
  int64_t iterations_ = 0;
};

// ClpModel::status() of a solve the event handler ended.
constexpr int kClpStoppedByEvent = 5;

class ClpSheetLp final : public SheetLp {
 public:
  ClpSheetLp(int num_columns, const ClpSheetLpOptions& options) : options_(options) {
    model_.setLogLevel(options.log_level);
    // 2048: no refactorization at the end of a solve of fewer than 20 pivots, to check the
    // answer. A warm pump solve takes a handful of pivots, and that refactorization was a fifth
    // of its CPU time (on a 10k-arc mesh 15% less CPU with it, q identical on the shared set).
    if (options.keep_factorization) model_.setSpecialOptions(model_.specialOptions() | 2048);
    model_.setFactorizationFrequency(options.factorization_frequency);
    if (options.dual_pricing == ClpDualPricing::kSteepestEdgeFromUnitWeights) {
      ClpDualRowSteepest pricing(/*mode=*/0);  // the model keeps a clone
      model_.setDualRowPivotAlgorithm(pricing);
    }
    const std::vector<double> lower(num_columns, 0.0), upper(num_columns, COIN_DBL_MAX),
        objective(num_columns, 0.0);
    const std::vector<CoinBigIndex> starts(num_columns + 1, 0);
    model_.loadProblem(num_columns, 0, starts.data(), nullptr, nullptr, lower.data(), upper.data(),
                       objective.data(), nullptr, nullptr);
    // Keep the factorization's arrays from one refactorization to the next (core/isp/
    // sparse_dual_simplex.cc, constructor, says why).
    model_.factorization()->setPersistenceFlag(1);
  }

  int num_columns() const override { return model_.numberColumns(); }
  int num_rows() const override { return model_.numberRows(); }

  void SetObjectiveCoefficient(int column, double value) override {
    model_.setObjectiveCoefficient(column, value);
  }
  void SetColumnBounds(int column, double lower, double upper) override {
    model_.setColumnBounds(column, ToClp(lower), ToClp(upper));
  }
  void SetRowBounds(int row, double lower, double upper) override {
    model_.setRowBounds(row, ToClp(lower), ToClp(upper));
  }

  void AddRows(const LpRowBatch& batch) override {
    if (batch.size() == 0) return;
    std::vector<double> lower(batch.size()), upper(batch.size());
    for (int i = 0; i < batch.size(); ++i) {
      lower[i] = ToClp(batch.lower()[i]);
      upper[i] = ToClp(batch.upper()[i]);
    }
    const std::vector<CoinBigIndex> starts(batch.starts().begin(), batch.starts().end());
    model_.addRows(batch.size(), lower.data(), upper.data(), starts.data(), batch.columns().data(),
                   batch.coefs().data());
    // The factorization of the old basis no longer matches the row count.
    fresh_factorization_needed_ = true;
  }

  bool wants_column_cap() const override { return true; }

  absl::StatusOr<LpOutcome> Solve() override {
    *stop_held_ = false;  // a stopped solve's verdict must not stop this one
    int flags = 0;
    if (options_.keep_factorization) {
      flags = 1;
      if (!fresh_factorization_needed_ && solved_once_) flags |= 2 | 4;
    }
    RunSimplex(flags);
    int status = model_.status();
    if (status != 0 && status != 1 && status != kClpStoppedByEvent) {
      // Numerical trouble from a stale basis: retry once from the slack basis.
      model_.allSlackBasis(true);
      RunSimplex(options_.keep_factorization ? 1 : 0);
      status = model_.status();
    }
    solved_once_ = true;
    // A stopped solve's factorization is not one to go on from.
    fresh_factorization_needed_ = status == kClpStoppedByEvent;
    if (status == kClpStoppedByEvent) return LpOutcome::kStopped;
    if (status == 0) return LpOutcome::kOptimal;
    if (status == 1) return LpOutcome::kInfeasible;
    return absl::InternalError(absl::StrCat("CLP failed with status ", status, " (secondary ",
                                            model_.secondaryStatus(), ") on ", model_.numberRows(),
                                            " rows x ", model_.numberColumns(), " columns"));
  }

  void SetStopCheck(LpStopCheck should_stop) override {
    // The model keeps a clone.
    const StopCheckHandler handler(std::move(should_stop), stop_held_);
    model_.passInEventHandler(&handler);
  }

  SheetLpCounters counters() const override { return {.pivots = pivots_}; }

  bool AppendBasis(std::vector<uint8_t>* is_basic) const override {
    for (int j = 0; j < model_.numberColumns(); ++j) {
      is_basic->push_back(model_.getColumnStatus(j) == ClpSimplex::basic);
    }
    for (int i = 0; i < model_.numberRows(); ++i) {
      is_basic->push_back(model_.getRowStatus(i) == ClpSimplex::basic);
    }
    return true;
  }

  std::span<const double> column_values() const override {
    return {model_.getColSolution(), static_cast<size_t>(model_.numberColumns())};
  }

 private:
  void RunSimplex(int flags) {
    if (options_.algorithm == ClpAlgorithm::kPrimal) {
      model_.primal(0, flags);
    } else {
      model_.dual(0, flags);
    }
    pivots_ += model_.numberIterations();
  }

  ClpSheetLpOptions options_;
  ClpSimplex model_;
  bool solved_once_ = false;
  bool fresh_factorization_needed_ = true;
  int64_t pivots_ = 0;
  std::shared_ptr<bool> stop_held_ = std::make_shared<bool>(false);  // see StopCheckHandler
};

}  // namespace

std::unique_ptr<SheetLp> NewClpSheetLp(int num_columns, const ClpSheetLpOptions& options) {
  return std::make_unique<ClpSheetLp>(num_columns, options);
}

SheetLpFactory ClpSheetLpFactory(const ClpSheetLpOptions& options) {
  return [options](int num_columns) { return NewClpSheetLp(num_columns, options); };
}

}  // namespace ispq
