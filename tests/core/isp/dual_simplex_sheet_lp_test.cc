// SPDX-License-Identifier: Apache-2.0
// What is specific to the sparse dual simplex back end of the sheet LPs (tests/core/isp/
// sheet_lp_test.cc runs the interface's contract on every back end, this one with several
// fallback settings): the solves it hands to CLP and when, that it goes on warm from CLP's basis,
// its counters, and its answers from the fallback's values.
#include "core/isp/dual_simplex_sheet_lp.h"

#include <algorithm>
#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "core/isp/clp_sheet_lp.h"
#include "core/isp/sheet_lp.h"
#include "core/isp/sparse_dual_simplex.h"
#include "core/lp_row_batch.h"
#include "gtest/gtest.h"

namespace ispq {
namespace {

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

// 60 random covering rows x_i + x_j >= 1 over 160 columns boxed in [0, 1], with positive costs:
// from the slack basis every row is violated, so a new objective takes dozens of dual pivots.
struct CoveringLp {
  static constexpr int kColumns = 160;
  explicit CoveringLp(int seed) : random(seed) {
    std::uniform_int_distribution<int> column(0, kColumns - 1);
    for (int r = 0; r < 60; ++r) {
      const int a = column(random), b = (a + 1 + column(random) % (kColumns - 1)) % kColumns;
      rows.Add(std::vector<int32_t>{a, b}, std::vector<double>{1, 1}, 1, kLpInfinity);
    }
    NewObjective();
  }
  void NewObjective() {
    costs.resize(kColumns);
    for (double& c : costs) c = cost(random);
  }
  // Changes a few costs: no new objective.
  void ChangeSomeCosts() {
    for (int k = 0; k < 3; ++k) costs[random() % kColumns] = cost(random);
  }
  void Load(SheetLp& lp, bool with_rows) const {
    if (with_rows) lp.AddRows(rows);
    for (int c = 0; c < kColumns; ++c) {
      lp.SetObjectiveCoefficient(c, costs[c]);
      lp.SetColumnBounds(c, 0, 1);
    }
  }
  std::unique_ptr<SheetLp> Fresh() const {
    std::unique_ptr<SheetLp> fresh = NewClpSheetLp(kColumns);
    Load(*fresh, true);
    return fresh;
  }

  std::mt19937 random;
  std::uniform_real_distribution<double> cost{0.1, 10};
  LpRowBatch rows;
  std::vector<double> costs;
};

TEST(DualSimplexSheetLpTest, NeedsNoColumnCapAndKeepsNoClpBasis) {
  std::unique_ptr<SheetLp> lp = NewDualSimplexSheetLp(2);
  EXPECT_FALSE(lp->wants_column_cap());
  std::vector<uint8_t> basis;
  EXPECT_FALSE(lp->AppendBasis(&basis));
}

// On a small LP a new objective is the sparse simplex's own work: no CLP, its pivots counted.
TEST(DualSimplexSheetLpTest, SolvesSmallLpsWithoutClp) {
  CoveringLp model(11);
  std::unique_ptr<SheetLp> live = NewDualSimplexSheetLp(CoveringLp::kColumns);
  model.Load(*live, true);
  for (int round = 0; round < 3; ++round) {
    SCOPED_TRACE("round " + std::to_string(round));
    std::unique_ptr<SheetLp> fresh = model.Fresh();
    ASSERT_NO_FATAL_FAILURE(ExpectSameAnswer(*live, *fresh, model.costs));
    model.NewObjective();
    model.Load(*live, false);
  }
  const SheetLpCounters counters = live->counters();
  EXPECT_GT(counters.pivots, 0);
  EXPECT_EQ(counters.fallback_solves, 0);
  EXPECT_EQ(counters.stalled_solves, 0);
  EXPECT_GE(counters.pivots, counters.degenerate_pivots);
}

// A solve the sparse simplex cannot finish (here: no pivots allowed) goes to CLP; the values it
// answers with are CLP's, nonzero columns included, and CLP's pivots count as its own.
TEST(DualSimplexSheetLpTest, ASolveItCannotFinishIsHandedToClp) {
  CoveringLp model(12);
  std::unique_ptr<SheetLp> live =
      NewDualSimplexSheetLp(CoveringLp::kColumns, {.max_iterations = 0});
  model.Load(*live, true);
  for (int round = 1; round <= 3; ++round) {
    SCOPED_TRACE("round " + std::to_string(round));
    std::unique_ptr<SheetLp> fresh = model.Fresh();
    ASSERT_NO_FATAL_FAILURE(ExpectSameAnswer(*live, *fresh, model.costs));
    EXPECT_EQ(live->counters().fallback_solves, round);
    EXPECT_GE(live->counters().pivots, fresh->counters().pivots);
    std::vector<int32_t> nonzero;
    live->AppendNonzeroColumns(&nonzero);
    std::sort(nonzero.begin(), nonzero.end());
    std::vector<int32_t> expected;
    for (int j = 0; j < CoveringLp::kColumns; ++j) {
      if (live->column_values()[j] != 0) expected.push_back(j);
    }
    EXPECT_EQ(nonzero, expected);
    model.NewObjective();
    model.Load(*live, false);
  }
}

// A new objective that needs more pivots than its budget (here one) is finished by CLP; cost
// edits that are no new objective stay with the sparse simplex.
TEST(DualSimplexSheetLpTest, ANewObjectiveOverItsPivotBudgetGoesToClp) {
  CoveringLp model(13);
  std::unique_ptr<SheetLp> live = NewDualSimplexSheetLp(
      CoveringLp::kColumns, {.new_objective_min_pivots = 1, .new_objective_pivots_per_row = 0});
  model.Load(*live, true);
  std::unique_ptr<SheetLp> fresh = model.Fresh();
  ASSERT_NO_FATAL_FAILURE(ExpectSameAnswer(*live, *fresh, model.costs));
  EXPECT_EQ(live->counters().fallback_solves, 1);
  for (int round = 0; round < 3; ++round) {
    model.ChangeSomeCosts();
    model.Load(*live, false);
    fresh = model.Fresh();
    ASSERT_NO_FATAL_FAILURE(ExpectSameAnswer(*live, *fresh, model.costs));
  }
  EXPECT_EQ(live->counters().fallback_solves, 1);
  model.NewObjective();
  model.Load(*live, false);
  fresh = model.Fresh();
  ASSERT_NO_FATAL_FAILURE(ExpectSameAnswer(*live, *fresh, model.costs));
  EXPECT_EQ(live->counters().fallback_solves, 2);
}

// A warm solve on a large LP gets a work budget from what CLP's last solve from scratch of it
// cost; past it, CLP solves it from scratch. The same edits with the budget off (an LP below
// warm_budget_min_columns) stay with the sparse simplex; both answer as fresh CLP models.
TEST(DualSimplexSheetLpTest, AWarmSolveOverItsWorkBudgetGoesToClp) {
  CoveringLp model(14);
  const SparseDualSimplexOptions tight = {
      .new_objective_clp_min_columns = 0, .warm_budget_min_columns = 0, .warm_budget_factor = 1e-9};
  const SparseDualSimplexOptions off = {.new_objective_clp_min_columns = 0,
                                        .warm_budget_min_columns = CoveringLp::kColumns + 1};
  std::unique_ptr<SheetLp> budgeted = NewDualSimplexSheetLp(CoveringLp::kColumns, tight);
  std::unique_ptr<SheetLp> unbudgeted = NewDualSimplexSheetLp(CoveringLp::kColumns, off);
  model.Load(*budgeted, true);
  model.Load(*unbudgeted, true);
  int64_t warm_pivots = 0;  // of the unbudgeted LP's warm solves
  for (int round = 0; round < 6; ++round) {
    SCOPED_TRACE("round " + std::to_string(round));
    const int64_t before = unbudgeted->counters().pivots;
    ASSERT_NO_FATAL_FAILURE(ExpectSameAnswer(*budgeted, *model.Fresh(), model.costs));
    ASSERT_NO_FATAL_FAILURE(ExpectSameAnswer(*unbudgeted, *model.Fresh(), model.costs));
    if (round > 0) warm_pivots += unbudgeted->counters().pivots - before;
    for (int k = 0; k < 10; ++k) model.ChangeSomeCosts();  // 30 of 160: still no new objective
    model.Load(*budgeted, false);
    model.Load(*unbudgeted, false);
  }
  ASSERT_GT(warm_pivots, 0) << "the cost changes must take the warm solves some pivots";
  EXPECT_EQ(unbudgeted->counters().fallback_solves, 1) << "only the first, a new objective";
  EXPECT_GT(budgeted->counters().fallback_solves, 1);
}

// After CLP solved a new objective, the sparse dual simplex goes on from CLP's basis: a few cost
// changes later it solves warm, without CLP (were the basis not taken back, every later solve
// would look like a new objective to it and go to CLP too), and answers as a fresh CLP model.
TEST(DualSimplexSheetLpTest, SolvesAfterOneByClpAreWarm) {
  constexpr int kPairs = 80;
  constexpr int kColumns = 2 * kPairs;
  std::mt19937 random(5);
  std::uniform_real_distribution<double> cost(-1, 10);
  std::uniform_int_distribution<int> pair(0, kPairs - 1);
  LpRowBatch rows;
  for (int r = 0; r < 60; ++r) {
    const int a = pair(random), b = (a + 1 + pair(random) % (kPairs - 1)) % kPairs;
    rows.Add(std::vector<int32_t>{2 * a, 2 * a + 1, 2 * b, 2 * b + 1},
             std::vector<double>{1, -1, -1, 1}, -1, kLpInfinity);
  }
  std::unique_ptr<SheetLp> live =
      DualSimplexSheetLpFactory({.new_objective_clp_min_columns = 0})(kColumns);
  live->AddRows(rows);
  std::vector<double> costs(kColumns);
  for (int c = 0; c < kColumns; ++c) {
    costs[c] = cost(random);
    live->SetObjectiveCoefficient(c, costs[c]);
    live->SetColumnBounds(c, 0, 1);  // boxed, as the bulk descent's unit moves
  }
  const absl::StatusOr<LpOutcome> first = live->Solve();
  ASSERT_TRUE(first.ok()) << first.status();
  ASSERT_EQ(*first, LpOutcome::kOptimal);
  ASSERT_EQ(live->counters().fallback_solves, 1) << "a new objective goes to CLP";
  for (int round = 0; round < 5; ++round) {
    for (int k = 0; k < 3; ++k) {
      const int c = static_cast<int>(random() % kColumns);
      costs[c] = cost(random);
      live->SetObjectiveCoefficient(c, costs[c]);
    }
    std::unique_ptr<SheetLp> fresh = NewClpSheetLp(kColumns);
    fresh->AddRows(rows);
    for (int c = 0; c < kColumns; ++c) {
      fresh->SetObjectiveCoefficient(c, costs[c]);
      fresh->SetColumnBounds(c, 0, 1);
    }
    SCOPED_TRACE("round " + std::to_string(round));
    ASSERT_NO_FATAL_FAILURE(ExpectSameAnswer(*live, *fresh, costs));
    EXPECT_EQ(live->counters().fallback_solves, 1);
  }
}

// Rows that hold on the whole column box are not given to CLP (they can never bind there), and the
// sparse simplex still has them: it goes on warm from CLP's basis with their logicals basic, and
// once a widened box lets them bind, they hold.
TEST(DualSimplexSheetLpTest, RowsThatHoldOnTheColumnBoxStayWithTheSparseSimplex) {
  constexpr int kColumns = 120;
  std::mt19937 random(7);
  std::uniform_real_distribution<double> cost(-1, 10);
  std::uniform_int_distribution<int> column(0, kColumns - 1);
  LpRowBatch rows;
  for (int r = 0; r < 90; ++r) {
    const int a = column(random), b = (a + 1 + column(random) % (kColumns - 1)) % kColumns;
    if (r % 3 == 0) {
      rows.Add(std::vector<int32_t>{a, b}, std::vector<double>{1, 1}, 1, kLpInfinity);
    } else {  // holds for x in [0, 1]^2, binds once b may exceed a by more than 1
      rows.Add(std::vector<int32_t>{a, b}, std::vector<double>{1, -1}, -1, kLpInfinity);
    }
  }
  std::vector<double> costs(kColumns);
  double upper = 1;
  auto load = [&](SheetLp& lp) {
    for (int c = 0; c < kColumns; ++c) {
      lp.SetObjectiveCoefficient(c, costs[c]);
      lp.SetColumnBounds(c, 0, upper);
    }
  };
  auto fresh = [&] {
    std::unique_ptr<SheetLp> lp = NewClpSheetLp(kColumns);
    lp->AddRows(rows);
    load(*lp);
    return lp;
  };
  std::unique_ptr<SheetLp> live =
      DualSimplexSheetLpFactory({.new_objective_clp_min_columns = 0})(kColumns);
  live->AddRows(rows);
  for (double& c : costs) c = cost(random);
  load(*live);
  ASSERT_NO_FATAL_FAILURE(ExpectSameAnswer(*live, *fresh(), costs));
  ASSERT_EQ(live->counters().fallback_solves, 1) << "a new objective goes to CLP";
  const int64_t pivots_by_clp = live->counters().pivots;
  for (int round = 0; round < 5; ++round) {
    SCOPED_TRACE("round " + std::to_string(round));
    for (int k = 0; k < 3; ++k) costs[random() % kColumns] = cost(random);
    load(*live);
    ASSERT_NO_FATAL_FAILURE(ExpectSameAnswer(*live, *fresh(), costs));
    EXPECT_EQ(live->counters().fallback_solves, 1);
  }
  // Warm from CLP's basis: a few cost changes take a few pivots, not another solve from scratch
  // (with the rows left out nonbasic the basis is singular, and the five rounds took 24 pivots
  // from the slack basis, as many as CLP's whole solve; warm they take none).
  EXPECT_LE(4 * (live->counters().pivots - pivots_by_clp), pivots_by_clp);
  upper = 3;  // now x_b - x_a may reach 3: the rows left out bind
  load(*live);
  ASSERT_NO_FATAL_FAILURE(ExpectSameAnswer(*live, *fresh(), costs));
  for (int c = 0; c < kColumns; ++c) ASSERT_LE(live->column_values()[c], upper + 1e-9);
}

}  // namespace
}  // namespace ispq
