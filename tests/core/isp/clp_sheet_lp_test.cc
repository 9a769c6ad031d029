// SPDX-License-Identifier: Apache-2.0
// What is specific to the CLP back end of the sheet LPs (tests/core/isp/sheet_lp_test.cc runs the
// interface's contract on every back end): it asks for the column cap, reports its basis and its
// pivots, and answers the same with and without the factorization kept between solves.
#include "core/isp/clp_sheet_lp.h"

#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "core/isp/sheet_lp.h"
#include "core/lp_row_batch.h"
#include "gtest/gtest.h"

namespace ispq {
namespace {

// x0 + x1 >= 2, x1 - x2 >= 0 with costs 1, 3, 1: the optimum x = (2, 0, 0).
std::unique_ptr<SheetLp> SmallLp(const ClpSheetLpOptions& options = {}) {
  std::unique_ptr<SheetLp> lp = NewClpSheetLp(3, options);
  LpRowBatch rows;
  rows.Add(std::vector<int32_t>{0, 1}, std::vector<double>{1, 1}, 2, kLpInfinity);
  rows.Add(std::vector<int32_t>{1, 2}, std::vector<double>{1, -1}, 0, kLpInfinity);
  lp->AddRows(rows);
  lp->SetObjectiveCoefficient(0, 1);
  lp->SetObjectiveCoefficient(1, 3);
  lp->SetObjectiveCoefficient(2, 1);
  return lp;
}

// CLP's dual simplex needs the free columns boxed (the sparse dual simplex does not).
TEST(ClpSheetLpTest, AsksForTheColumnCap) { EXPECT_TRUE(NewClpSheetLp(1)->wants_column_cap()); }

// After an optimal solve the basis has one basic variable per row: here x0 (row 0 tight) and
// row 1's activity x1 - x2 = 0, which sits at its bound but is what the dual simplex keeps basic
// or not; whatever CLP picks, the count is the number of rows and the values agree.
TEST(ClpSheetLpTest, ReportsItsBasisAndPivots) {
  std::unique_ptr<SheetLp> lp = SmallLp();
  EXPECT_EQ(lp->counters().pivots, 0);
  const absl::StatusOr<LpOutcome> outcome = lp->Solve();
  ASSERT_TRUE(outcome.ok()) << outcome.status();
  ASSERT_EQ(*outcome, LpOutcome::kOptimal);
  EXPECT_NEAR(lp->column_values()[0], 2, 1e-9);
  EXPECT_NEAR(lp->column_values()[1], 0, 1e-9);
  EXPECT_NEAR(lp->column_values()[2], 0, 1e-9);
  std::vector<uint8_t> is_basic = {7};  // appended to, not replaced
  ASSERT_TRUE(lp->AppendBasis(&is_basic));
  ASSERT_EQ(is_basic.size(), 1u + 3u + 2u);
  int basic = 0;
  for (size_t i = 1; i < is_basic.size(); ++i) basic += is_basic[i];
  EXPECT_EQ(basic, lp->num_rows());
  EXPECT_TRUE(is_basic[1]) << "x0 = 2 lies strictly inside its bounds";
  const int64_t pivots = lp->counters().pivots;
  EXPECT_GT(pivots, 0);
  // Pivots add up over solves; CLP hands nothing to another solver.
  lp->SetObjectiveCoefficient(0, 5);  // now x1 = 2 (cost 6) beats x0 = 2 (cost 10)
  ASSERT_TRUE(lp->Solve().ok());
  EXPECT_NEAR(lp->column_values()[0], 0, 1e-9);
  EXPECT_NEAR(lp->column_values()[1], 2, 1e-9);
  EXPECT_GE(lp->counters().pivots, pivots + 1);
  EXPECT_EQ(lp->counters().fallback_solves, 0);
  EXPECT_EQ(lp->counters().refactorizations, 0);
}

// The same edits with and without CLP's work areas kept between solves (and with the primal
// simplex, and with the dual's steepest edge weights started at one) give the same optima, also
// after rows are appended to a solved model.
TEST(ClpSheetLpTest, TheOptionsChangeNoAnswer) {
  constexpr int kColumns = 16;
  std::vector<std::unique_ptr<SheetLp>> lps;
  lps.push_back(NewClpSheetLp(kColumns, {.keep_factorization = true}));
  lps.push_back(NewClpSheetLp(kColumns, {.keep_factorization = false}));
  lps.push_back(NewClpSheetLp(kColumns, {.algorithm = ClpAlgorithm::kPrimal}));
  lps.push_back(
      NewClpSheetLp(kColumns, {.dual_pricing = ClpDualPricing::kSteepestEdgeFromUnitWeights}));
  std::mt19937 random(3);
  std::uniform_real_distribution<double> cost(0.1, 10);
  std::uniform_int_distribution<int> column(0, kColumns - 1);
  for (auto& lp : lps) {
    for (int c = 0; c < kColumns; ++c) lp->SetColumnBounds(c, 0, 50);
  }
  std::vector<double> costs(kColumns, 0);
  for (int step = 0; step < 30; ++step) {
    SCOPED_TRACE("step " + std::to_string(step));
    LpRowBatch rows;
    if (step % 3 == 0) {
      const int a = column(random), b = column(random);
      if (a != b) {
        rows.Add(std::vector<int32_t>{a, b}, std::vector<double>{1, 1}, 1 + step % 4, kLpInfinity);
      }
    }
    const int c = column(random);
    costs[c] = cost(random);
    const double lower = static_cast<double>(random() % 3);
    for (auto& lp : lps) {
      lp->AddRows(rows);
      lp->SetObjectiveCoefficient(c, costs[c]);
      lp->SetColumnBounds(c, lower, 50);
    }
    std::vector<double> objectives;
    for (auto& lp : lps) {
      const absl::StatusOr<LpOutcome> outcome = lp->Solve();
      ASSERT_TRUE(outcome.ok()) << outcome.status();
      ASSERT_EQ(*outcome, LpOutcome::kOptimal);
      double objective = 0;
      for (int j = 0; j < kColumns; ++j) objective += costs[j] * lp->column_values()[j];
      objectives.push_back(objective);
    }
    EXPECT_NEAR(objectives[1], objectives[0], 1e-7);
    EXPECT_NEAR(objectives[2], objectives[0], 1e-7);
    EXPECT_NEAR(objectives[3], objectives[0], 1e-7);
  }
}

}  // namespace
}  // namespace ispq
