// SPDX-License-Identifier: Apache-2.0
// Every back end of the sheet LPs (core/isp/sheet_lp.h): known optima, infeasibility, and
// warm-started solves after in-place edits agreeing with CLP's solves of freshly built models.
#include "core/isp/sheet_lp.h"

#include <cstdint>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "core/isp/clp_sheet_lp.h"
#include "core/isp/dual_simplex_sheet_lp.h"
#include "core/isp/lcd_scaling.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace ispq {
namespace {

using ::testing::DoubleNear;
using ::testing::ElementsAre;
using ::testing::Optional;

void AddRow(SheetLp& lp, std::vector<int32_t> columns, std::vector<double> coefs, double lower,
            double upper) {
  LpRowBatch batch;
  batch.Add(columns, coefs, lower, upper);
  lp.AddRows(batch);
}

double Objective(const SheetLp& lp, const std::vector<double>& costs) {
  double sum = 0;
  for (size_t i = 0; i < costs.size(); ++i) sum += costs[i] * lp.column_values()[i];
  return sum;
}

// Solves both; the warm-started `live` must answer as the freshly built CLP model `fresh`.
void ExpectSameAnswer(SheetLp& live, SheetLp& fresh, const std::vector<double>& costs) {
  const absl::StatusOr<LpOutcome> a = live.Solve();
  const absl::StatusOr<LpOutcome> b = fresh.Solve();
  ASSERT_TRUE(a.ok()) << a.status();
  ASSERT_TRUE(b.ok()) << b.status();
  ASSERT_EQ(*a, *b);
  if (*a == LpOutcome::kOptimal) {
    EXPECT_NEAR(Objective(live, costs), Objective(fresh, costs), 1e-7);
  }
}

struct BackEnd {
  std::string name;
  SheetLpFactory factory;
};

class SheetLpTest : public ::testing::TestWithParam<BackEnd> {
 protected:
  std::unique_ptr<SheetLp> NewLp(int columns) { return GetParam().factory(columns); }
};

// A sheet through a root in the smallest possible LP: x0 = x1 (consistency), x0 >= 1 (pump).
TEST_P(SheetLpTest, PumpedRootPropagatesThroughConsistency) {
  std::unique_ptr<SheetLp> lp = NewLp(3);
  EXPECT_EQ(lp->num_columns(), 3);
  AddRow(*lp, {0, 1}, {1, -1}, 0, 0);
  AddRow(*lp, {1, 2}, {1, -1}, 0, kLpInfinity);  // x2 <= x1
  EXPECT_EQ(lp->num_rows(), 2);
  lp->SetObjectiveCoefficient(0, 1);
  lp->SetObjectiveCoefficient(1, 2);
  lp->SetObjectiveCoefficient(2, 5);
  lp->SetColumnBounds(0, 1, kLpInfinity);
  const absl::StatusOr<LpOutcome> outcome = lp->Solve();
  ASSERT_TRUE(outcome.ok()) << outcome.status();
  EXPECT_EQ(*outcome, LpOutcome::kOptimal);
  EXPECT_THAT(lp->column_values(),
              ElementsAre(DoubleNear(1, 1e-9), DoubleNear(1, 1e-9), DoubleNear(0, 1e-9)));
}

TEST_P(SheetLpTest, ReportsInfeasibilityAndRecovers) {
  std::unique_ptr<SheetLp> lp = NewLp(2);
  AddRow(*lp, {0, 1}, {1, 1}, 2, kLpInfinity);
  lp->SetObjectiveCoefficient(0, 1);
  lp->SetObjectiveCoefficient(1, 1);
  lp->SetColumnBounds(0, 0, 0.5);
  lp->SetColumnBounds(1, 0, 0.5);
  absl::StatusOr<LpOutcome> outcome = lp->Solve();
  ASSERT_TRUE(outcome.ok()) << outcome.status();
  EXPECT_EQ(*outcome, LpOutcome::kInfeasible);
  lp->SetColumnBounds(1, 0, kLpInfinity);
  outcome = lp->Solve();
  ASSERT_TRUE(outcome.ok()) << outcome.status();
  EXPECT_EQ(*outcome, LpOutcome::kOptimal);
  EXPECT_NEAR(lp->column_values()[0] + lp->column_values()[1], 2, 1e-9);
}

// The odd cycle x0 + x1 >= 1, x1 + x2 >= 1, x0 + x2 >= 1 has the half-integral optimum 1/2 each,
// like the T-junction U-turns of the paper's Figs. 6 and 7: lcd 2.
TEST_P(SheetLpTest, HalfIntegralVertexHasLcdTwo) {
  std::unique_ptr<SheetLp> lp = NewLp(3);
  AddRow(*lp, {0, 1}, {1, 1}, 1, kLpInfinity);
  AddRow(*lp, {1, 2}, {1, 1}, 1, kLpInfinity);
  AddRow(*lp, {0, 2}, {1, 1}, 1, kLpInfinity);
  for (int c = 0; c < 3; ++c) lp->SetObjectiveCoefficient(c, 1);
  const absl::StatusOr<LpOutcome> outcome = lp->Solve();
  ASSERT_TRUE(outcome.ok()) << outcome.status();
  ASSERT_EQ(*outcome, LpOutcome::kOptimal);
  const std::vector<double> x(lp->column_values().begin(), lp->column_values().end());
  EXPECT_THAT(x, ElementsAre(DoubleNear(0.5, 1e-9), DoubleNear(0.5, 1e-9), DoubleNear(0.5, 1e-9)));
  EXPECT_THAT(LeastCommonDenominator(x), Optional(2));
}

// A sequence of edits of the kinds the quantizer makes (weights, root bounds, row bounds,
// appended rows) on one live model must give the optimum of a model built from scratch.
TEST_P(SheetLpTest, WarmStartedSolvesMatchFreshModels) {
  constexpr int kColumns = 12;
  std::mt19937 random(7);
  std::uniform_real_distribution<double> cost(0.1, 10);
  std::uniform_int_distribution<int> column(0, kColumns - 1);
  std::uniform_int_distribution<int> small(-2, 2);

  struct Row {
    std::vector<int32_t> columns;
    std::vector<double> coefs;
    double lower;
  };
  std::vector<Row> rows;
  std::vector<double> costs(kColumns, 1.0);
  std::vector<std::pair<double, double>> bounds(kColumns, {0.0, kLpInfinity});
  std::unique_ptr<SheetLp> live = NewLp(kColumns);
  for (int c = 0; c < kColumns; ++c) live->SetObjectiveCoefficient(c, costs[c]);
  auto add_row = [&](Row row) {
    rows.push_back(row);
    AddRow(*live, row.columns, row.coefs, row.lower, kLpInfinity);
  };
  // Paired columns (2i, 2i + 1) as in the sheet LP: rows use +c on one and -c on the other.
  for (int i = 0; i < 4; ++i) {
    Row row;
    for (int k = 0; k < 3; ++k) {
      const int pair = column(random) / 2;
      const double c = k == 0 ? 1.0 : (small(random) >= 0 ? 1.0 : -1.0);
      row.columns.push_back(2 * pair);
      row.coefs.push_back(c);
      row.columns.push_back(2 * pair + 1);
      row.coefs.push_back(-c);
    }
    row.lower = small(random);
    add_row(row);
  }
  for (int step = 0; step < 40; ++step) {
    for (int k = 0; k < 3; ++k) {
      const int c = column(random);
      costs[c] = cost(random);
      live->SetObjectiveCoefficient(c, costs[c]);
    }
    const int root = column(random);
    for (auto& b : bounds) b = {0.0, kLpInfinity};
    bounds[root] = {1.0, kLpInfinity};
    bounds[root ^ 1] = {0.0, 0.0};
    for (int c = 0; c < kColumns; ++c) live->SetColumnBounds(c, bounds[c].first, bounds[c].second);
    const int r = static_cast<int>(random() % rows.size());
    rows[r].lower = small(random);
    live->SetRowBounds(r, rows[r].lower, kLpInfinity);
    if (step % 10 == 9) {
      Row row;
      row.columns = {2 * (column(random) / 2)};
      row.coefs = {1};
      row.lower = -1;
      add_row(row);
    }

    std::unique_ptr<SheetLp> fresh = NewClpSheetLp(kColumns);
    for (const Row& row : rows) AddRow(*fresh, row.columns, row.coefs, row.lower, kLpInfinity);
    for (int c = 0; c < kColumns; ++c) {
      fresh->SetObjectiveCoefficient(c, costs[c]);
      fresh->SetColumnBounds(c, bounds[c].first, bounds[c].second);
    }
    SCOPED_TRACE("step " + std::to_string(step));
    ASSERT_NO_FATAL_FAILURE(ExpectSameAnswer(*live, *fresh, costs));
  }
}

// A new objective now and then (every cost changed: the switch of weight schemes, a separating
// update), few changes in between. The dual simplex may hand a new objective to CLP and go on
// from where it stopped; every answer must still be the optimum of the model as it stands.
TEST_P(SheetLpTest, NewObjectivesBetweenWarmSolvesMatchFreshModels) {
  constexpr int kPairs = 80;  // more columns than a "new objective" needs changed (100)
  constexpr int kColumns = 2 * kPairs;
  std::mt19937 random(11);
  std::uniform_real_distribution<double> cost(0.1, 10);
  std::uniform_int_distribution<int> pair(0, kPairs - 1);
  std::uniform_int_distribution<int> bound(-2, 2);
  // Consistency-like rows x_a - x_a' - x_b + x_b' >= lower over random pairs a != b.
  LpRowBatch rows;
  std::vector<std::vector<int32_t>> row_columns;
  for (int r = 0; r < 60; ++r) {
    const int a = pair(random), b = (a + 1 + pair(random) % (kPairs - 1)) % kPairs;
    row_columns.push_back({2 * a, 2 * a + 1, 2 * b, 2 * b + 1});
  }
  const std::vector<double> coefs = {1, -1, -1, 1};
  for (const auto& columns : row_columns) rows.Add(columns, coefs, bound(random), kLpInfinity);
  std::unique_ptr<SheetLp> live = NewLp(kColumns);
  live->AddRows(rows);
  std::vector<double> costs(kColumns, 1.0);
  for (int step = 0; step < 30; ++step) {
    const bool new_objective = step % 5 == 0;
    for (int k = 0; k < (new_objective ? kColumns : 3); ++k) {
      costs[new_objective ? k : static_cast<int>(random() % kColumns)] = cost(random);
    }
    const int root = pair(random);
    std::unique_ptr<SheetLp> fresh = NewClpSheetLp(kColumns);
    fresh->AddRows(rows);
    for (SheetLp* lp : {live.get(), fresh.get()}) {
      for (int c = 0; c < kColumns; ++c) {
        lp->SetObjectiveCoefficient(c, costs[c]);
        lp->SetColumnBounds(c, 0, kLpInfinity);
      }
      lp->SetColumnBounds(2 * root, 1, kLpInfinity);
      lp->SetColumnBounds(2 * root + 1, 0, 0);
    }
    SCOPED_TRACE("step " + std::to_string(step));
    ASSERT_NO_FATAL_FAILURE(ExpectSameAnswer(*live, *fresh, costs));
  }
}

// A stop check that holds ends a solve long before its optimum, with kStopped, on every back end
// (the sparse simplex, CLP, and the sparse simplex's fallback to CLP); the solve that follows
// without it finishes from wherever the stopped one left, with the answer of a fresh model.
TEST_P(SheetLpTest, AStopCheckThatHoldsEndsTheSolveAndTheNextOneFinishes) {
  // 1500 covering rows x_a + x_b + x_c >= 1 over 3000 columns: from the slack basis every row is
  // violated, so the solve takes hundreds of pivots (more than the few hundred the stop check
  // lets go by below, on every back end).
  constexpr int kColumns = 3000;
  std::mt19937 random(5);
  std::uniform_int_distribution<int> column(0, kColumns - 1);
  std::uniform_real_distribution<double> cost(0.1, 10);
  LpRowBatch rows;
  for (int r = 0; r < 1500; ++r) {
    rows.Add(std::vector<int32_t>{column(random), column(random), column(random)},
             std::vector<double>{1, 1, 1}, 1, kLpInfinity);
  }
  std::vector<double> costs(kColumns);
  for (double& c : costs) c = cost(random);
  std::unique_ptr<SheetLp> live = NewLp(kColumns);
  std::unique_ptr<SheetLp> fresh = NewClpSheetLp(kColumns);
  for (SheetLp* lp : {live.get(), fresh.get()}) {
    lp->AddRows(rows);
    for (int c = 0; c < kColumns; ++c) {
      lp->SetObjectiveCoefficient(c, costs[c]);
      lp->SetColumnBounds(c, 0, 1);
    }
  }
  int asked = 0;
  live->SetStopCheck([&asked] { return ++asked >= 3; });
  const absl::StatusOr<LpOutcome> stopped = live->Solve();
  ASSERT_TRUE(stopped.ok()) << stopped.status();
  EXPECT_EQ(*stopped, LpOutcome::kStopped);
  EXPECT_EQ(asked, 3) << "asked until it held, then no more";
  const int64_t pivots_when_stopped = live->counters().pivots;

  live->SetStopCheck({});
  ASSERT_NO_FATAL_FAILURE(ExpectSameAnswer(*live, *fresh, costs));
  EXPECT_EQ(asked, 3);
  EXPECT_GT(live->counters().pivots, pivots_when_stopped);
}

INSTANTIATE_TEST_SUITE_P(
    BackEnds, SheetLpTest,
    ::testing::Values(BackEnd{"SparseDualSimplex", DualSimplexSheetLpFactory()},
                      BackEnd{"ClpDual", ClpSheetLpFactory({.algorithm = ClpAlgorithm::kDual})},
                      BackEnd{"ClpPrimal", ClpSheetLpFactory({.algorithm = ClpAlgorithm::kPrimal})},
                      // Every solve handed to the CLP fallback.
                      BackEnd{"SparseDualSimplexFallback",
                              DualSimplexSheetLpFactory({.max_iterations = 0})},
                      // Every new objective handed to CLP after one pivot.
                      BackEnd{"SparseDualSimplexNewObjectivesToClp",
                              DualSimplexSheetLpFactory({.new_objective_min_pivots = 1,
                                                         .new_objective_pivots_per_row = 0})},
                      // Every new objective handed to CLP at once, its basis taken back.
                      BackEnd{"SparseDualSimplexNewObjectivesToClpAtOnce",
                              DualSimplexSheetLpFactory({.new_objective_clp_min_columns = 0})}),
    [](const auto& info) { return info.param.name; });

}  // namespace
}  // namespace ispq
