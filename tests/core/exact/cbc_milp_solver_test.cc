// SPDX-License-Identifier: Apache-2.0
// The CBC back end of MilpSolver on hand-made models with known optima: integrality of the flagged
// columns only, the objective offset in every reported value and in the cutoff, infeasibility of
// the MILP and of its relaxation, an initial solution, and failure on an unbounded relaxation.
// (tests/core/exact/quantization_milp_test.cc runs it on the quantization model itself.)
#include "core/exact/cbc_milp_solver.h"

#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <vector>

#include "core/exact/milp_model.h"
#include "core/exact/milp_solver.h"
#include "core/lp_row_batch.h"
#include "gtest/gtest.h"

namespace ispq {
namespace {

class Recorder : public MilpCallbacks {
 public:
  bool OnIncumbent(std::span<const double> columns, double objective) override {
    EXPECT_EQ(static_cast<int>(columns.size()), num_columns);
    incumbents.push_back(objective);
    return true;
  }
  bool OnProgress(double bound, int64_t) override {
    bounds.push_back(bound);
    return true;
  }
  int num_columns = 0;
  std::vector<double> incumbents;
  std::vector<double> bounds;
};

void AddRow(MilpModel& model, std::vector<int32_t> columns, std::vector<double> coefs, double lower,
            double upper) {
  model.rows.Add(columns, coefs, lower, upper);
}

// min 5 + x + y with 2x + 2y >= 3 over integers 0..10: optimum 7 (x + y = 2), relaxation 6.5.
MilpModel Covering() {
  MilpModel model;
  model.AddColumn(0, 10, 1, true);
  model.AddColumn(0, 10, 1, true);
  AddRow(model, {0, 1}, {2, 2}, 3, kLpInfinity);
  model.objective_offset = 5;
  return model;
}

TEST(CbcMilpSolverTest, SolvesASmallMilpAndReportsWithTheOffset) {
  const MilpModel model = Covering();
  const std::unique_ptr<MilpSolver> solver = NewCbcMilpSolver();
  Recorder recorder;
  recorder.num_columns = model.num_columns();
  const absl::StatusOr<MilpResult> result = solver->Solve(model, {}, recorder);
  ASSERT_TRUE(result.ok()) << result.status();
  EXPECT_EQ(result->status, MilpStatus::kOptimal);
  EXPECT_NEAR(result->best_objective, 7, 1e-9);
  EXPECT_NEAR(result->bound, 7, 1e-9);
  ASSERT_TRUE(result->best.has_value());
  ASSERT_EQ(result->best->size(), 2u);
  EXPECT_NEAR((*result->best)[0] + (*result->best)[1], 2, 1e-9);
  for (double v : *result->best) EXPECT_NEAR(v, std::round(v), 1e-9);
  // Every incumbent is reported with the offset, the last one being the optimum; no bound the
  // solver reports along the way exceeds it.
  ASSERT_FALSE(recorder.incumbents.empty());
  EXPECT_NEAR(recorder.incumbents.back(), 7, 1e-9);
  for (double objective : recorder.incumbents) EXPECT_GE(objective, 7 - 1e-9);
  for (double bound : recorder.bounds) EXPECT_LE(bound, 7 + 1e-9);

  const absl::StatusOr<LpResult> relaxation = solver->SolveRelaxation(model);
  ASSERT_TRUE(relaxation.ok()) << relaxation.status();
  EXPECT_EQ(relaxation->status, LpStatus::kOptimal);
  EXPECT_NEAR(relaxation->objective, 6.5, 1e-9);
}

// Only flagged columns are integral: min -2x - y with x + y <= 2.5, x <= 1.7, x integer: x = 1,
// y = 1.5 (objective -3.5); the relaxation takes x = 1.7, y = 0.8 (-4.2).
TEST(CbcMilpSolverTest, OnlyFlaggedColumnsAreIntegral) {
  MilpModel model;
  model.AddColumn(0, kLpInfinity, -2, true);
  model.AddColumn(0, kLpInfinity, -1, false);
  AddRow(model, {0, 1}, {1, 1}, -kLpInfinity, 2.5);
  AddRow(model, {0}, {1}, -kLpInfinity, 1.7);
  const std::unique_ptr<MilpSolver> solver = NewCbcMilpSolver();
  Recorder recorder;
  recorder.num_columns = 2;
  const absl::StatusOr<MilpResult> result = solver->Solve(model, {}, recorder);
  ASSERT_TRUE(result.ok()) << result.status();
  EXPECT_EQ(result->status, MilpStatus::kOptimal);
  EXPECT_NEAR(result->best_objective, -3.5, 1e-9);
  ASSERT_TRUE(result->best.has_value());
  EXPECT_NEAR((*result->best)[0], 1, 1e-9);
  EXPECT_NEAR((*result->best)[1], 1.5, 1e-9);
  const absl::StatusOr<LpResult> relaxation = solver->SolveRelaxation(model);
  ASSERT_TRUE(relaxation.ok());
  EXPECT_NEAR(relaxation->objective, -4.2, 1e-9);
}

// The cutoff is on the objective with its offset: nothing below 7 exists, something below 7.5
// does.
TEST(CbcMilpSolverTest, TheCutoffIncludesTheOffset) {
  const MilpModel model = Covering();
  const std::unique_ptr<MilpSolver> solver = NewCbcMilpSolver();
  Recorder recorder;
  recorder.num_columns = model.num_columns();
  MilpSolveOptions at_optimum;
  at_optimum.cutoff = 7 - 1e-6;
  absl::StatusOr<MilpResult> result = solver->Solve(model, at_optimum, recorder);
  ASSERT_TRUE(result.ok()) << result.status();
  EXPECT_EQ(result->status, MilpStatus::kInfeasible);
  EXPECT_FALSE(result->best.has_value());
  EXPECT_EQ(result->bound, at_optimum.cutoff);

  MilpSolveOptions above;
  above.cutoff = 7.5;
  result = solver->Solve(model, above, recorder);
  ASSERT_TRUE(result.ok()) << result.status();
  EXPECT_EQ(result->status, MilpStatus::kOptimal);
  EXPECT_NEAR(result->best_objective, 7, 1e-9);
}

// A worse initial solution is the first best and is improved on; the best is never worse.
TEST(CbcMilpSolverTest, StartsFromAnInitialSolution) {
  const MilpModel model = Covering();
  const std::unique_ptr<MilpSolver> solver = NewCbcMilpSolver();
  Recorder recorder;
  recorder.num_columns = model.num_columns();
  MilpSolveOptions options;
  options.initial_solution = std::vector<double>{4, 3};  // objective 12
  const absl::StatusOr<MilpResult> result = solver->Solve(model, options, recorder);
  ASSERT_TRUE(result.ok()) << result.status();
  EXPECT_EQ(result->status, MilpStatus::kOptimal);
  EXPECT_NEAR(result->best_objective, 7, 1e-9);

  // Given the optimum itself, the solver proves it.
  options.initial_solution = std::vector<double>{0, 2};
  Recorder quiet;
  quiet.num_columns = model.num_columns();
  const absl::StatusOr<MilpResult> proved = solver->Solve(model, options, quiet);
  ASSERT_TRUE(proved.ok()) << proved.status();
  EXPECT_EQ(proved->status, MilpStatus::kOptimal);
  EXPECT_NEAR(proved->best_objective, 7, 1e-9);
}

// 2x = 1 has a fractional solution only: the MILP is infeasible, its relaxation is not; x >= 2
// with x <= 1 makes the relaxation infeasible too.
TEST(CbcMilpSolverTest, ReportsInfeasibleModelsAndRelaxations) {
  MilpModel odd;
  odd.AddColumn(0, 5, 1, true);
  AddRow(odd, {0}, {2}, 1, 1);
  const std::unique_ptr<MilpSolver> solver = NewCbcMilpSolver();
  Recorder recorder;
  recorder.num_columns = 1;
  const absl::StatusOr<MilpResult> result = solver->Solve(odd, {}, recorder);
  ASSERT_TRUE(result.ok()) << result.status();
  EXPECT_EQ(result->status, MilpStatus::kInfeasible);
  EXPECT_FALSE(result->best.has_value());
  EXPECT_TRUE(recorder.incumbents.empty());
  absl::StatusOr<LpResult> relaxation = solver->SolveRelaxation(odd);
  ASSERT_TRUE(relaxation.ok());
  EXPECT_EQ(relaxation->status, LpStatus::kOptimal);
  EXPECT_NEAR(relaxation->objective, 0.5, 1e-9);

  MilpModel contradictory;
  contradictory.AddColumn(0, 1, 1, false);
  AddRow(contradictory, {0}, {1}, 2, kLpInfinity);
  relaxation = solver->SolveRelaxation(contradictory);
  ASSERT_TRUE(relaxation.ok());
  EXPECT_EQ(relaxation->status, LpStatus::kInfeasible);
}

TEST(CbcMilpSolverTest, AnUnboundedRelaxationIsAnError) {
  MilpModel unbounded;
  unbounded.AddColumn(-kLpInfinity, kLpInfinity, -1, false);
  AddRow(unbounded, {0}, {1}, 0, kLpInfinity);
  EXPECT_FALSE(NewCbcMilpSolver()->SolveRelaxation(unbounded).ok());
}

}  // namespace
}  // namespace ispq
